#!/usr/bin/env python3
"""Checks that every citation of docs/method.md points to a section that exists.

  check_method_citations.py REPO_ROOT

A citation is "method.md" followed by section numbers: "§3", "§1.4, §2", "section 5".
"§N" needs a heading "## N." in docs/method.md; "§N.M" also needs item "M." of section N's
numbered list. Prints each broken citation with its file and line and exits 1.
"""
import pathlib
import re
import sys

CITATION = re.compile(r"method\.md(?:'s)?((?:[\s,;and]*(?:§|section\s+)\d+(?:\.\d+)?)*)")
NUMBER = re.compile(r"(\d+)(?:\.(\d+))?")


def sections(method_text):
    """{section number: set of its numbered-list items}"""
    found, current = {}, None
    for line in method_text.splitlines():
        heading = re.match(r"## (\d+)\.", line)
        if heading:
            current = int(heading.group(1))
            found[current] = set()
            continue
        item = re.match(r"(\d+)\. ", line)
        if item and current is not None:
            found[current].add(int(item.group(1)))
    return found


def main(root):
    root = pathlib.Path(root)
    method = root / "docs" / "method.md"
    if not method.exists():
        print(f"{method}: missing, but cited")
        return 1
    known = sections(method.read_text())
    files = [root / "README.md", *sorted((root / "docs").glob("*.md"))]
    for folder in ("src", "include", "apps", "tests", "examples", "scripts", "bench"):
        files += sorted(p for p in (root / folder).rglob("*") if p.suffix in {".cpp", ".hpp", ".toml", ".sh", ".md"})
    broken, cited = [], 0
    for path in files:
        if path == method:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), start=1):
            for citation in CITATION.finditer(line):
                cited += 1
                for section, item in NUMBER.findall(citation.group(1)):
                    section = int(section)
                    if section not in known:
                        broken.append(f"{path.relative_to(root)}:{number}: method.md §{section} does not exist")
                    elif item and int(item) not in known[section]:
                        broken.append(f"{path.relative_to(root)}:{number}: method.md §{section}.{item}: "
                                      f"section {section} has no item {item}")
    for b in broken:
        print(b)
    if cited == 0:
        print("no citation of method.md found: the scan is broken")
        return 1
    print(f"{cited} citations of docs/method.md, {len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))

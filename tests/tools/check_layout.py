#!/usr/bin/env python3
"""The house rules of docs/ARCHITECTURE.md, checked on the sources:

- no file under src/, include/, apps/ or python/src/ longer than MAX_FILE_LINES lines;
- no function longer than MAX_FUNCTION_LINES lines (from its opening brace's line to its
  closing brace's, lambdas inside counted with it);
- every `#include "aggpack/<module>/..."` of a module names itself or a module below it
  (MODULE_DEPENDENCIES, the targets' dependencies in src/CMakeLists.txt).

    python3 tests/tools/check_layout.py REPO_ROOT

Prints each breach and exits 1 when there is one. The function finder is a brace counter on
the text with comments, strings and character literals blanked: enough for this code base's
style (clang-format, one definition per line), not a C++ parser.
"""
import pathlib
import re
import sys

MAX_FILE_LINES = 600
MAX_FUNCTION_LINES = 80

# Each module and the modules it may include (besides itself), as in src/CMakeLists.txt.
MODULE_DEPENDENCIES = {
    "core": set(),
    "sizes": {"core"},
    "models": {"sizes"},
    "spatial": {"core"},
    "grains": {"core"},
    "deposition": {"core", "spatial"},
    "analysis": {"core", "spatial", "grains"},
    "dynamics": {"core", "spatial", "deposition"},
    "report": {"core"},
    "io": {"core", "sizes", "deposition", "dynamics", "grains"},
    "lammps": {"io", "dynamics"},
    "run": {"io", "report", "analysis", "dynamics", "models", "lammps"},
    "studies": {"run"},
    "specimen": {"analysis", "io"},
    "labtests": {"studies"},
    "blends": {"labtests"},
}


def below(module):
    """Every module `module` may include: its dependencies, transitively."""
    seen, todo = set(), [module]
    while todo:
        for dep in MODULE_DEPENDENCIES[todo.pop()]:
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return seen


def blanked(text):
    """The text with comments, literals and preprocessor lines replaced by spaces (lines kept)."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|R"([^(]*)\(.*?\)\1"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'',
                         re.S)
    text = pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
    # Preprocessor lines too: an #include would otherwise join the head of the next brace.
    return re.sub(r"(?m)^[ \t]*#[^\n]*", lambda m: " " * len(m.group(0)), text)


def long_functions(text):
    """(first line, lines, signature) of every function body longer than MAX_FUNCTION_LINES."""
    code = blanked(text)
    scopes, found = [], []  # scopes: ("namespace" | "class" | "function" | "block", first line, head)
    head_start, line = 0, 1
    for i, c in enumerate(code):
        if c == "\n":
            line += 1
        elif c in ";":
            head_start = i + 1
        elif c == "{":
            head = " ".join(code[head_start:i].split())
            enclosing = scopes[-1][0] if scopes else "namespace"
            if re.match(r"(inline\s+)?namespace\b|extern\s*$", head):
                kind = "namespace"
            elif re.search(r"\b(struct|class|union|enum)\b[^(]*$", head):
                kind = "class"
            elif enclosing in ("namespace", "class") and "(" in head and not head.endswith("="):
                kind = "function"
            else:
                kind = "block"
            scopes.append((kind, line, head))
            head_start = i + 1
        elif c == "}":
            if scopes:
                kind, first, head = scopes.pop()
                if kind == "function" and line - first + 1 > MAX_FUNCTION_LINES:
                    found.append((first, line - first + 1, head[-90:]))
            head_start = i + 1
    return found


def module_of(path, root):
    parts = path.relative_to(root).parts
    if parts[0] == "src" and len(parts) > 2:
        return parts[1]
    if parts[:2] == ("include", "aggpack") and len(parts) > 3:
        return parts[2]
    return None


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    breaches = []
    sources = [p for d in ("src", "include", "apps", "python/src") for p in sorted((root / d).rglob("*"))
               if p.suffix in (".cpp", ".hpp", ".in")]
    for path in sources:
        text = path.read_text(encoding="utf-8")
        name = path.relative_to(root)
        lines = text.count("\n")
        if lines > MAX_FILE_LINES:
            breaches.append(f"{name}: {lines} lines (at most {MAX_FILE_LINES})")
        for first, length, head in long_functions(text):
            breaches.append(f"{name}:{first}: a function of {length} lines (at most {MAX_FUNCTION_LINES}): {head}")
        module = module_of(path, root)
        if module is None:
            continue
        if module not in MODULE_DEPENDENCIES:
            breaches.append(f"{name}: module {module} is not in the module table (tests/tools/check_layout.py)")
            continue
        allowed = below(module) | {module}
        for n, text_line in enumerate(text.splitlines(), 1):
            m = re.match(r'\s*#\s*include\s*"aggpack/([a-z_]+)/', text_line)
            if m and m.group(1) not in allowed:
                breaches.append(f"{name}:{n}: {module} includes {m.group(1)}, which is not below it")
    for b in breaches:
        print(b)
    print(f"{len(sources)} files checked, {len(breaches)} breach{'es' if len(breaches) != 1 else ''}")
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())

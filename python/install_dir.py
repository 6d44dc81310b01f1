"""Where `cmake --install` puts the aggpack package for an install prefix: where this
interpreter (or a virtual environment's own) looks for packages.

    install_dir.py PREFIX     prints the folder; a note on stderr when it is not on the path

- a virtual environment (PREFIX/pyvenv.cfg): its interpreter's site-packages;
- the user base (~/.local, or PYTHONUSERBASE): the user site, ~/.local/lib/python3.11/site-packages;
- a prefix the interpreter searches (/usr/local: Debian's /usr/local/lib/python3.11/dist-packages);
- any other prefix: PREFIX/lib/python3.11/site-packages, which then needs PYTHONPATH.
"""
import os
import site
import subprocess
import sys
import sysconfig


def main():
    prefix = os.path.realpath(sys.argv[1])
    if os.path.exists(os.path.join(prefix, "pyvenv.cfg")):
        own = os.path.join(prefix, "bin", "python3")
        print(subprocess.check_output([own, "-c", "import sysconfig; print(sysconfig.get_path('platlib'))"],
                                      text=True).strip())
        return
    if prefix == os.path.realpath(site.getuserbase()):
        print(site.getusersitepackages())
        return
    for path in sys.path:  # the interpreter's own folders under the prefix (lib/..., not local/lib/...)
        relative = os.path.relpath(os.path.realpath(path), prefix) if path else ".."
        if relative.startswith("lib" + os.sep) and os.path.basename(path) in ("dist-packages", "site-packages"):
            print(path)
            return
    folder = sysconfig.get_path("platlib", "posix_prefix", vars={"base": prefix, "platbase": prefix})
    print(f"aggpack: {folder} is not on {sys.executable}'s path: import aggpack with PYTHONPATH={folder}",
          file=sys.stderr)
    print(folder)


if __name__ == "__main__":
    main()

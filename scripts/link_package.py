"""Make the build tree's hoembed package importable from the venv (a .pth file)."""

import pathlib
import sys
import sysconfig

build = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "build").resolve()
candidates = sorted(build.glob("lib*/python3*/site-packages/hoembed/__init__.py"))
if not candidates:
    sys.exit(f"link_package: no hoembed package under {build}")
site = candidates[0].parent.parent
pth = pathlib.Path(sysconfig.get_paths()["purelib"]) / "hoembed-build.pth"
if not pth.exists() or pth.read_text().strip() != str(site):
    pth.write_text(str(site) + "\n")

# The `hoembed` command in the venv.
script = pathlib.Path(sys.executable).parent / "hoembed"
body = f"#!{sys.executable}\nimport sys\nfrom hoembed.cli import main\nsys.exit(main())\n"
if not script.exists() or script.read_text() != body:
    script.write_text(body)
    script.chmod(0o755)

"""Install the repaired wheel into a clean venv and use it like a user would (``make wheel-test``).

The venv is made by the standard library's ``venv`` without the build requirements (no cmake, ninja,
pybind11, scikit-build-core); pip installs only the wheel and its runtime dependencies. Checks, each
failing with a one-line message (exit code 1):

1. the wheel is tagged ``manylinux_*`` (auditwheel repair ran) and bundles SUNDIALS, ERFA and pugixml
   under ``satgnc.libs/``;
2. ``ldd`` of the installed extension resolves every SUNDIALS / ERFA / pugixml library to the bundled
   copy, never to /usr/lib;
3. the README's first Python code block (the quick start) runs in that venv, from a directory outside
   the source tree, with an empty LD_LIBRARY_PATH;
4. ``satgnc reproduce --help`` exits with 0.

Usage: python scripts/check_wheel.py WHEELHOUSE_DIR VENV_DIR
"""

from __future__ import annotations

import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUNDLED = ("sundials", "erfa", "pugixml")


def fail(msg: str) -> None:
    print(f"check_wheel: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def readme_blocks() -> list[str]:
    """The ```python blocks of README.md, in order."""
    return re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), flags=re.S)


def main(argv: list[str]) -> int:
    t0 = time.perf_counter()
    wheelhouse, venv = pathlib.Path(argv[0]).resolve(), pathlib.Path(argv[1]).resolve()
    wheels = sorted(wheelhouse.glob("satgnc-*.whl"))
    if len(wheels) != 1:
        fail(f"{wheelhouse}: expected one satgnc wheel, found {[w.name for w in wheels]}")
    whl = wheels[0]
    if "manylinux" not in whl.name:
        fail(f"{whl.name}: not tagged manylinux (auditwheel repair did not run)")
    names = zipfile.ZipFile(whl).namelist()
    libs = [n for n in names if n.startswith("satgnc.libs/")]
    for lib in BUNDLED:
        if not any(lib in n for n in libs):
            fail(f"{whl.name}: no bundled {lib} library in satgnc.libs/ (has {libs})")
    print(f"check_wheel: {whl.name}: bundles {[pathlib.Path(n).name for n in libs]}")

    shutil.rmtree(venv, ignore_errors=True)
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH", "VIRTUAL_ENV")}
    env["PATH"] = f"{venv / 'bin'}:/usr/bin:/bin"
    subprocess.run([str(py), "-m", "pip", "install", "-q", str(whl)], check=True, env=env)
    for tool in ("cmake", "ninja", "pybind11-config"):
        if (venv / "bin" / tool).exists():
            fail(f"{venv}: has {tool}: not a venv without build tools")

    out = subprocess.run([str(py), "-c", "import satgnc._satgnc as m; print(m.__file__)"], env=env,
                         capture_output=True, text=True, check=True, cwd=tempfile.gettempdir())
    so = out.stdout.strip()
    if not so.startswith(str(venv)):
        fail(f"satgnc imported from {so}, not from the clean venv {venv}")
    ldd = subprocess.run(["ldd", so], capture_output=True, text=True, check=True).stdout
    for line in ldd.splitlines():
        if any(lib in line for lib in BUNDLED):
            if "satgnc.libs" not in line:
                fail(f"ldd {so}: {line.strip()}: not the bundled copy")
            print(f"check_wheel: ldd: {line.strip()}")
    if "not found" in ldd:
        fail(f"ldd {so}: unresolved libraries:\n{ldd}")

    blocks = readme_blocks()
    if not blocks:
        fail("README.md has no ```python block (the quick start)")
    with tempfile.TemporaryDirectory() as d:
        r = subprocess.run([str(py), "-c", blocks[0]], env=env, cwd=d, capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"README quick start failed in the clean venv:\n{r.stderr}")
        print("check_wheel: README quick start ran in the clean venv")
        r = subprocess.run([str(venv / "bin" / "satgnc"), "reproduce", "--help"], env=env, cwd=d,
                           capture_output=True, text=True)
        if r.returncode != 0 or "usage" not in r.stdout:
            fail(f"satgnc reproduce --help exited with {r.returncode}: {r.stderr}")
    print(f"check_wheel: OK in {time.perf_counter() - t0:.1f} s (venv, install, checks)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

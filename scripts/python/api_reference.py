"""Writes docs/python_api.md, the reference of the Python package `flank`
from its docstrings and signatures (what `help(flank.X)` shows), in the
order of `flank.__all__`.

    target/ci-venv/bin/python scripts/python/api_reference.py          # write
    target/ci-venv/bin/python scripts/python/api_reference.py --check  # fail if stale

python/tests/test_api_reference.py runs the check, so a changed docstring
or signature that is not in the page fails the tests."""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs/python_api.md"

HEADER = """# The Python package `flank`: API reference

Generated from the docstrings and signatures of the installed package by
`scripts/python/api_reference.py` (do not edit by hand; the tests fail when
this page and the package differ). The guide is [python.md](python.md).

"""


def _doc(obj) -> str:
    d = inspect.getdoc(obj)
    return (d or "(no docstring)").strip()


def _signature(name: str, obj) -> str:
    try:
        return f"{name}{inspect.signature(obj)}"
    except (TypeError, ValueError):
        return name


def _members(cls):
    for n, m in inspect.getmembers(cls):
        if n.startswith("_") and n != "__init__":
            continue
        if n == "__init__" and (m is object.__init__ or not inspect.isfunction(m)):
            continue
        # members defined by this class or a flank base, not by object/Mapping
        owner = next((c for c in cls.__mro__ if n in vars(c)), None)
        if owner is None or not getattr(owner, "__module__", "").startswith("flank"):
            continue
        yield n, m


def page() -> str:
    import flank

    out = [HEADER, f"Version {flank.__version__}, summary schema {flank.SCHEMA_VERSION}.\n\n"]
    out.append("## Module `flank`\n\n" + _doc(flank) + "\n\n")
    for name in flank.__all__:
        obj = getattr(flank, name)
        if name in ("__version__", "SCHEMA_VERSION"):
            continue
        if inspect.isclass(obj):
            out.append(f"## class `{name}`\n\n{_doc(obj)}\n\n")
            for n, m in _members(obj):
                if isinstance(inspect.getattr_static(obj, n), property):
                    out.append(f"### `{name}.{n}` (property)\n\n{_doc(m)}\n\n")
                elif callable(m):
                    out.append(f"### `{name}.{_signature(n, m)}`\n\n{_doc(m)}\n\n")
        elif callable(obj):
            out.append(f"## `{_signature(name, obj)}`\n\n{_doc(obj)}\n\n")
        else:
            out.append(f"## `{name}`\n\n{obj!r}\n\n")
    return "".join(out).rstrip() + "\n"


def main() -> int:
    text = page()
    if "--check" in sys.argv:
        if not PAGE.is_file() or PAGE.read_text(encoding="utf-8") != text:
            print(f"{PAGE} is stale: run python scripts/python/api_reference.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(text, encoding="utf-8")
    print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""docs/python_api.md is the package's reference as its docstrings and
signatures give it today (scripts/python/api_reference.py)."""

from __future__ import annotations

import importlib.util

from conftest import ROOT


def test_the_api_reference_page_is_current():
    spec = importlib.util.spec_from_file_location("api_reference", ROOT / "scripts/python/api_reference.py")
    ref = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ref)
    page = ref.page()
    on_disk = ref.PAGE.read_text(encoding="utf-8") if ref.PAGE.is_file() else ""
    assert on_disk == page, "docs/python_api.md is stale: run python scripts/python/api_reference.py"
    # every public name has its section
    import flank

    for name in flank.__all__:
        if name not in ("__version__", "SCHEMA_VERSION"):
            assert f"`{name}" in page, name

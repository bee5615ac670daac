"""Scenes: load, from a string, get and set keys with the CLI's validation;
errors as exceptions with file, line and key."""

from __future__ import annotations

import pytest

import flank
from conftest import ROOT, SEED002, SEED003

BAD = ROOT / "tests/bad_inputs/scene"


def test_load_and_get():
    s = flank.load_scene(SEED002)
    assert s.kind == "spur"
    assert s.get("load.torque_nm") == 312.0
    assert s.get("pinion.teeth") == 13
    assert str(s.path) == str(SEED002)
    with pytest.raises(KeyError):
        s.get("pinion.no_such_key")
    assert flank.load_scene(SEED003).kind == "hypoid"


def test_set_validates_and_a_refused_value_names_the_key():
    s = flank.load_scene(SEED002)
    s.set("load.torque_nm", 104.0)
    assert s.get("load.torque_nm") == 104.0
    assert s.overrides == {"load.torque_nm": 104.0}
    with pytest.raises(flank.SceneError) as e:
        s.set("load.torque_nm", -1.0)
    assert e.value.key == "load.torque_nm"
    assert e.value.file == str(SEED002)
    assert isinstance(e.value.line, int) and e.value.line >= 1
    assert "with the overrides load.torque_nm" in str(e.value)
    # the refused value left the scene as it was
    assert s.get("load.torque_nm") == 104.0
    # a copy does not share later overrides
    c = s.copy()
    c.set("load.torque_nm", 50)
    assert s.get("load.torque_nm") == 104.0 and c.get("load.torque_nm") == 50


def test_overrides_reach_the_analysis():
    light = flank.load_scene(SEED002, {"load.torque_nm": 104.0})
    full = flank.check(SEED002)
    # the check of the overridden scene is still a check of the same pair
    assert flank.check(light).contact_ratio == full.contact_ratio
    assert 1.3 < full.contact_ratio < 1.9


def test_bad_scene_file_raises_with_file_line_and_key():
    with pytest.raises(flank.SceneError) as e:
        flank.load_scene(BAD / "gear_module_mismatch.toml")
    err = e.value
    assert err.file.endswith("gear_module_mismatch.toml")
    assert err.line == 23
    assert err.key == "gear.normal_module_mm"
    assert err.kind == "Parse"
    assert isinstance(err, flank.FlankError)
    assert "must equal `pinion.normal_module_mm`" in str(err)


def test_scene_from_string_names_its_path_in_errors():
    text = SEED002.read_text()
    s = flank.scene_from_string(text, path=SEED002)
    assert s.kind == "spur" and s.get("pinion.teeth") == 13
    broken = text.replace("[load]", "[load]\nno_such_key = 1", 1)
    with pytest.raises(flank.SceneError) as e:
        flank.scene_from_string(broken, path="inline.toml")
    assert e.value.file == "inline.toml"
    line = next(i for i, l in enumerate(broken.splitlines(), 1) if l.startswith("no_such_key"))
    assert e.value.line == line


def test_missing_file_is_an_error_naming_it(tmp_path):
    with pytest.raises(flank.FlankError) as e:
        flank.load_scene(tmp_path / "nope.toml")
    assert "nope.toml" in str(e.value)

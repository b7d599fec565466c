"""The crane file: loading, writing back, variants, and rejection of bad values by field name."""

from __future__ import annotations

import dataclasses
import math

import pytest

from cranepredict.crane import Crane


def test_patu655_loads_with_sourced_values(crane):
    assert crane.name == "PATU 655"
    assert crane.lift_boom.mass == 143.66
    assert crane.geometry.tilt_pivot == (2.881081, 0.021593)
    assert crane.lift_cylinder.bore == 0.1 and crane.tilt_cylinder.stroke_max == 0.78
    assert "outer_boom.izz" in crane.estimates


def test_toml_round_trip(crane, tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(crane.to_toml())
    assert Crane.from_toml(path) == crane


def test_with_load_changes_only_the_load(crane):
    heavy = crane.with_load(500)
    assert heavy.load_mass == 500.0 and crane.load_mass == 200.0
    assert dataclasses.replace(heavy, load_mass=200.0) == crane
    with pytest.raises(ValueError, match="load_mass"):
        crane.with_load(-1)
    with pytest.raises(TypeError, match="load_mass"):
        crane.with_load("heavy")


def _edited(crane, path, value):
    d = crane.to_dict()
    node = d
    keys = path.split(".")
    for k in keys[:-1]:
        node = node[k]
    node[keys[-1]] = value
    return d


@pytest.mark.parametrize("path, value, exc, words", [
    ("lift_boom.mass", 0.0, ValueError, "lift_boom.mass must be > 0"),
    ("outer_boom.izz", -1.0, ValueError, "outer_boom.izz must be > 0"),
    ("load_mass", -5.0, ValueError, "load_mass must be >= 0"),
    ("gravity", math.nan, ValueError, "gravity must be finite"),
    ("lift_cylinder.stroke_max", 0.0, ValueError, "lift_cylinder.stroke_min"),
    ("tilt_cylinder.rod", 0.2, ValueError, "tilt_cylinder.bore"),
    ("tilt_cylinder.friction.static", 100.0, ValueError, "tilt_cylinder.friction.static"),
    ("lift_cylinder.friction.stribeck_velocity", 0.0, ValueError, "stribeck_velocity must be > 0"),
    ("geometry.lift_pivot", [1.0], TypeError, "geometry.lift_pivot must be a pair"),
    ("geometry.tip_distance", "far", TypeError, "geometry.tip_distance must be a number"),
    ("lift_boom.mass", True, TypeError, "lift_boom.mass must be a number"),
    ("geometry.extension_min", 2.0, ValueError, "geometry.extension_min"),
])
def test_bad_field_is_named(crane, path, value, exc, words):
    with pytest.raises(exc, match=words.replace("[", r"\[").replace(".", r"\.")):
        Crane.from_dict(_edited(crane, path, value))


def test_unknown_and_missing_fields_are_named(crane):
    d = crane.to_dict()
    d["lift_boom"]["maas"] = 1.0
    with pytest.raises(ValueError, match="lift_boom.maas"):
        Crane.from_dict(d)
    d = crane.to_dict()
    del d["tilt_cylinder"]["friction"]["viscous"]
    with pytest.raises(ValueError, match="tilt_cylinder.friction.viscous is missing"):
        Crane.from_dict(d)


def test_four_bar_that_cannot_close_over_the_tilt_stroke_is_rejected(crane):
    # A tilt cylinder 3 m long cannot reach: the side-link triangle cannot close.
    with pytest.raises(ValueError, match="four-bar"):
        Crane.from_dict(_edited(crane, "tilt_cylinder.stroke_max", 3.0))
    # Side link 2 too short to reach the outer boom at some strokes.
    with pytest.raises(ValueError, match="four-bar"):
        Crane.from_dict(_edited(crane, "geometry.link2_end", [-0.1, 0.0]))


def test_lift_triangle_that_passes_its_dead_centre_is_rejected(crane):
    # A rod eye so close to the pivot that the lift stroke would fold the triangle flat.
    with pytest.raises(ValueError, match="lift triangle|four-bar|gamma"):
        Crane.from_dict(_edited(crane, "geometry.lift_cylinder_rod", [0.05, -0.01]))


def test_bad_toml_text():
    with pytest.raises(ValueError, match="not valid TOML"):
        Crane.from_toml_string("name = ")

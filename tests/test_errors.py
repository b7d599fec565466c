"""Every error names the input at fault: huge ints, tables where pairs are
expected, wrong types in crane dataclasses built directly, files that are not UTF-8, batches that
are not sequences, absurd stroke rates."""

from __future__ import annotations

import dataclasses

import pytest

import cranepredict as cp

STATE = dict(lift_stroke=0.1, tilt_stroke=0.3)
INPUTS = cp.Inputs(lift=cp.Pressure(100e5, 0), tilt=cp.Hold())


@pytest.mark.parametrize("rate", [1e300, -1e300, 1e10, 10.5])
@pytest.mark.parametrize("name", ["lift_stroke_rate", "tilt_stroke_rate"])
def test_a_stroke_rate_of_1e300_blames_the_stroke_rate(name, rate):
    with pytest.raises(ValueError, match=rf"State.{name} must be in \[-10, 10\] m/s "
                                         r"\(cranepredict.STROKE_RATE_MAX\)"):
        cp.State(**STATE, **{name: rate})


def test_stroke_rates_up_to_the_limit_are_accepted(crane):
    state = cp.State(**STATE, lift_stroke_rate=cp.STROKE_RATE_MAX)
    c = cp.predict(crane, state, INPUTS, 0.05)
    py = cp.predict(crane, state, INPUTS, 0.05, backend="python")
    assert abs(c.tip - py.tip).max() < 1e-9


# -- huge Python ints (a bare OverflowError before) ---------------------------------------------

HUGE = 10 ** 400


@pytest.mark.parametrize("make, words", [
    (lambda: cp.State(lift_stroke=HUGE, tilt_stroke=0.3), "State.lift_stroke"),
    (lambda: cp.State(**STATE, slew=-HUGE), "State.slew"),
    (lambda: cp.Pressure(p_a=HUGE), "Pressure.p_a"),
    (lambda: cp.PressureSeries(t=[0, HUGE], p_a=[0, 0], p_b=[0, 0]), "PressureSeries.t"),
    (lambda: cp.Crane.patu655().with_load(HUGE), "load_mass"),
])
def test_a_huge_int_is_a_value_error_naming_the_field(make, words):
    with pytest.raises(ValueError, match=words):
        make()


def test_a_huge_horizon_is_a_value_error_naming_horizon(crane):
    with pytest.raises(ValueError, match="horizon must be a finite number, got an int of 1329 bits"):
        cp.predict(crane, cp.State(**STATE), INPUTS, HUGE)
    with pytest.raises(ValueError, match="horizon must be a finite number"):
        cp.predict_many(crane, [cp.State(**STATE)], [INPUTS], HUGE)


def test_a_huge_sample_every_is_a_value_error_naming_sample_every(crane):
    with pytest.raises(ValueError, match=r"sample_every must be an int in \[1, 1,048,576\]"):
        cp.predict_many(crane, [cp.State(**STATE)], [INPUTS], 1.0, sample_every=HUGE)


def _crane_text(crane, section, key, value):
    text = crane.to_toml()
    head = f"\n[{section}]\n"
    start = text.index(head) + len(head)
    end = text.index("\n[", start) if "\n[" in text[start:] else len(text)
    lines = text[start:end].splitlines()
    lines = [f"{key} = {value}" if ln.split(" = ")[0] == key else ln for ln in lines]
    return text[:start] + "\n".join(lines) + text[end:]


def test_a_huge_mass_in_the_crane_file_names_the_mass(crane):
    with pytest.raises(ValueError, match=r"lift_boom.mass must be a finite number, got an int of"):
        cp.Crane.from_toml_string(_crane_text(crane, "lift_boom", "mass", "9" * 400))


# -- crane files and crane dataclasses ---------------------------------------------------------

def test_com_as_a_table_names_the_body_and_the_expected_form(crane):
    text = _crane_text(crane, "outer_boom", "com", "{x = 1.0, y = 0.0}")
    with pytest.raises(TypeError, match=r"outer_boom.com must be a pair \[x, y\] of numbers, as in "
                                        r"`com = \[0.5, 0.1\]`, got \{'x': 1.0, 'y': 0.0\} \(a table\)"):
        cp.Crane.from_toml_string(text)


def test_a_crane_file_that_is_not_utf8_names_the_file(crane, tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(("# Kran mit Ausleger \u00fc\n" + crane.to_toml()).encode("latin-1"))
    with pytest.raises(ValueError, match=r"crane file '.*latin1.toml' is not UTF-8 text .*at byte offset 20, b'.xfc'"):
        cp.Crane.from_toml(path)


# -- predict_many's sequences --------------------------------------------------------------------

@pytest.mark.parametrize("initials, inputs_list, words", [
    (None, None, "initials must be a sequence of cranepredict.State, got NoneType"),
    ([cp.State(**STATE)], None, "inputs_list must be a sequence of cranepredict.Inputs, got NoneType"),
    (cp.State(**STATE), [INPUTS], "initials must be a sequence of cranepredict.State, got State"),
    ([cp.State(**STATE)], INPUTS, "inputs_list must be a sequence of cranepredict.Inputs, got Inputs"),
    ("states", [INPUTS], "initials must be a sequence of cranepredict.State, got str"),
])
def test_predict_many_names_a_batch_that_is_not_a_sequence(crane, initials, inputs_list, words):
    with pytest.raises(TypeError, match=words):
        cp.predict_many(crane, initials, inputs_list, 2.0)


def test_a_huge_horizon_in_a_scenario_names_the_file_and_field():
    data = {"name": "x", "horizon": HUGE, "initial": STATE,
            "inputs": {"lift": {"hold": True}, "tilt": {"hold": True}}}
    with pytest.raises(ValueError, match="huge.toml.horizon must be a finite number"):
        cp.scenarios.from_dict(data, "huge.toml")


@pytest.mark.parametrize("change, name", [
    (lambda c: dataclasses.replace(c, gravity=HUGE), "gravity"),
    (lambda c: dataclasses.replace(c, lift_boom=dataclasses.replace(c.lift_boom, mass=HUGE)),
     "lift_boom.mass"),
    (lambda c: dataclasses.replace(c, outer_boom=dataclasses.replace(c.outer_boom, com=(0.1, -HUGE))),
     r"outer_boom.com\[1\]"),
    (lambda c: dataclasses.replace(c, tilt_cylinder=dataclasses.replace(
        c.tilt_cylinder, friction=dataclasses.replace(c.tilt_cylinder.friction, coulomb=HUGE))),
     "tilt_cylinder.friction.coulomb"),
])
def test_a_huge_int_in_a_crane_built_directly_names_the_field(crane, change, name):
    with pytest.raises(ValueError, match=rf"^{name} must be a finite number, got an int too large"):
        change(crane)


# The finding's messages were "unhashable type: 'list'" (a list com, hashed by the old cache) and
# "too many values to unpack" (a point of three numbers, unpacked into the C struct).
@pytest.mark.parametrize("change, exc, words", [
    (lambda c: dataclasses.replace(c, lift_boom=cp.Body(mass=100.0, com=[0.5, 0.1], izz=10.0)),
     TypeError, r"lift_boom.com must be a pair \(x, y\) of numbers, got \[0.5, 0.1\]"),
    (lambda c: dataclasses.replace(c, geometry=dataclasses.replace(c.geometry, lift_pivot=(0.1, 1.4, 0.0))),
     TypeError, r"geometry.lift_pivot must be a pair \(x, y\) of numbers, got \(0.1, 1.4, 0.0\)"),
    (lambda c: dataclasses.replace(c, lift_boom={"mass": 100.0}), TypeError,
     "lift_boom must be a Body, got dict"),
    (lambda c: dataclasses.replace(c, gravity="9.81"), TypeError, "gravity must be a number, got str"),
])
def test_crane_dataclasses_built_directly_with_wrong_types_name_the_field(crane, change, exc, words):
    with pytest.raises(exc, match=words):
        change(crane)


@pytest.mark.parametrize("change, exc, words", [
    (lambda d: d.pop("name"), ValueError, r"odd.toml: missing field\(s\) \['name'\]"),
    (lambda d: d.pop("horizon"), ValueError, r"odd.toml: missing field\(s\) \['horizon'\]"),
    (lambda d: d["initial"].update(lift_speed=0.1), ValueError,
     r"odd.toml.initial: unknown field\(s\) \['lift_speed'\]; allowed: "),
    (lambda d: d["initial"].pop("tilt_stroke"), TypeError, r"odd.toml.initial: .*tilt_stroke"),
    (lambda d: d.update(initial=[0.1, 0.3]), TypeError, "odd.toml.initial must be a table"),
])
def test_a_scenario_file_error_names_the_file_and_field(change, exc, words):
    """Was KeyError: 'name', or State.__init__() got an unexpected keyword argument."""
    data = {"name": "x", "horizon": 1.0, "initial": dict(STATE),
            "inputs": {"lift": {"hold": True}, "tilt": {"hold": True}}}
    change(data)
    with pytest.raises(exc, match=words):
        cp.scenarios.from_dict(data, "odd.toml")


# ValveSeries had the gap PressureSeries had: a huge int in a sampled signal gave a bare
# "OverflowError: int too large to convert to float".
@pytest.mark.parametrize("make, name", [
    (lambda: cp.ValveSeries(t=[0.0, HUGE], u=[0.0, 0.0]), "ValveSeries.t"),
    (lambda: cp.ValveSeries(t=[0.0, 2.0], u=[0.0, HUGE]), "ValveSeries.u"),
    (lambda: cp.PressureSeries(t=[0.0, HUGE], p_a=[0.0, 0.0], p_b=[0.0, 0.0]), "PressureSeries.t"),
])
def test_a_huge_int_in_a_sampled_signal_names_the_field(make, name):
    with pytest.raises(ValueError, match=rf"^{name} must be finite: it holds an int too large"):
        make()

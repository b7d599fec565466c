"""The FMU export: FMI 3.0 and 2.0 co-simulation units whose doStep is the C core's crane_step,
checked through FMPy (an importer that is not ours) against cranepredict.predict."""

import dataclasses
import importlib
import random
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cranepredict as cp

fmpy = pytest.importorskip("fmpy", reason="the [fmu] extra (FMPy) is not installed")
pytestmark = [pytest.mark.fmu,
              pytest.mark.skipif(not any(shutil.which(c) for c in ("cc", "gcc", "clang")),
                                 reason="exporting an FMU compiles it: no C compiler on PATH")]

from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from cranepredict.fmu import export_fmu  # noqa: E402

POSE = {"lift_stroke": 0.116, "tilt_stroke": 0.20}   # the paper's and lever-open's pose
OUT = ["tip_x", "tip_y", "tip_z", "lift_stroke", "tilt_stroke", "lift_p_a", "lift_p_b",
       "tilt_p_a", "tilt_p_b", "slew", "extension"]
STOPS = ["lift_stop", "tilt_stop", "slew_stop", "extension_stop"]
# a beam above lever-open's tip: the guard warns of the contact coming closer as the boom rises
BEAM = cp.World.from_toml_string("""
name = "beam"
margin = 0.30
[[obstacle]]
name = "beam"
kind = "box"
centre = [4.6, 0.0, 2.2]
size = [2.0, 10.0, 0.3]
yaw = 0.0
""")


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    """The FMUs the tests run, exported once: lever FMUs (lift and tilt levers; all four levers)
    and pressure FMUs, each in FMI 3 and 2."""
    d = tmp_path_factory.mktemp("fmu")
    crane = cp.Crane.patu655()
    out = {}
    for fmi in (3, 2):
        out["levers2", fmi] = export_fmu(crane, d / f"levers2-{fmi}.fmu", fmi=fmi,
                                         levers=["lift", "tilt"], start=POSE)
        out["levers4", fmi] = export_fmu(crane, d / f"levers4-{fmi}.fmu", fmi=fmi, start=POSE)
        out["pressure", fmi] = export_fmu(crane, d / f"pressure-{fmi}.fmu", fmi=fmi,
                                          drive="pressure", start=POSE)
        out["guard", fmi] = export_fmu(crane, d / f"guard-{fmi}.fmu", fmi=fmi,
                                       levers=["lift", "tilt"], start=POSE, world=BEAM)
    return out


class Unit:
    """One instance of an FMU through FMPy's low-level API (FMI 3 or 2), by variable name."""

    def __init__(self, path, name="crane", log=None):
        self.md = read_model_description(path)
        self.fmi = 3 if self.md.fmiVersion.startswith("3") else 2
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.type = {v.name: v.type for v in self.md.modelVariables}
        self.dir = extract(path)
        cls = FMU3Slave if self.fmi == 3 else FMU2Slave
        ident = self.md.coSimulation.modelIdentifier
        self.fmu = cls(guid=self.md.guid, unzipDirectory=self.dir, modelIdentifier=ident,
                       instanceName=name)
        if self.fmi == 3:
            self.fmu.instantiate(logMessage=log)
        else:
            self.fmu.instantiate()
        self.t = 0.0

    def set(self, **values):
        for k, v in values.items():
            if self.type[k] == "Boolean":
                self.fmu.setBoolean([self.vr[k]], [bool(v)])
            elif self.fmi == 3:
                self.fmu.setFloat64([self.vr[k]], [float(v)])
            else:
                self.fmu.setReal([self.vr[k]], [float(v)])

    def init(self, **params):
        if self.fmi == 3:
            self.fmu.enterInitializationMode(startTime=0.0)
        else:
            self.fmu.setupExperiment(startTime=0.0)
            self.fmu.enterInitializationMode()
        self.set(**params)
        self.fmu.exitInitializationMode()
        return self

    def get(self, names=OUT):
        vrs = [self.vr[n] for n in names]
        if self.fmi == 3:
            return np.array(self.fmu.getFloat64(vrs))
        return np.array(self.fmu.getReal(vrs))

    def stops(self):
        vrs = [self.vr[n] for n in STOPS]
        return np.array(self.fmu.getInt32(vrs) if self.fmi == 3 else self.fmu.getInteger(vrs))

    def step(self, h):
        self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)
        self.t += h

    def run(self, steps):
        rows, stops = [self.get()], [self.stops()]
        for h in steps:
            self.step(h)
            rows.append(self.get())
            stops.append(self.stops())
        return np.array(rows), np.array(stops)

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def _predicted(traj, every):
    """The trajectory's outputs at every every-th sample, in OUT's order."""
    cols = [traj.tip[:, 0], traj.tip[:, 1], traj.tip[:, 2], traj.strokes[:, 0], traj.strokes[:, 1],
            traj.p_a[:, 0], traj.p_b[:, 0], traj.p_a[:, 1], traj.p_b[:, 1],
            np.broadcast_to(traj.slew, traj.t.shape), np.broadcast_to(traj.extension, traj.t.shape)]
    return np.stack(cols, axis=1)[::every], traj.stop[::every]


def _assert_outputs(got, stops, want, want_stops):
    np.testing.assert_allclose(got[:, :5], want[:, :5], rtol=0, atol=1e-9)      # tip, strokes, m
    np.testing.assert_allclose(got[:, 5:9], want[:, 5:9], rtol=1e-9, atol=1e-3)  # pressures, Pa
    np.testing.assert_allclose(got[:, 9:], want[:, 9:], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(stops, want_stops)


@pytest.mark.parametrize("kind", ["levers2", "levers4", "pressure", "guard"])
@pytest.mark.parametrize("fmi", [3, 2])
def test_fmpy_validate_finds_no_problem(fmus, kind, fmi):
    assert validate_fmu(str(fmus[kind, fmi])) == []


@pytest.mark.parametrize("fmi", [3, 2])
def test_lever_open_equals_predict(fmus, fmi):
    """The operator's version of the paper's experiment: 2 s at 10-ms communication steps."""
    sc = cp.scenarios.get("lever-open")
    u = Unit(fmus["levers2", fmi]).init(load_mass=sc.crane.load_mass, lift_lever=1.0,
                                        tilt_lever=0.0)
    got, stops = u.run([0.01] * 200)
    u.close()
    want, want_stops = _predicted(cp.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt=0.005, method="rk4"), 2)
    _assert_outputs(got, stops, want, want_stops)


@pytest.mark.parametrize("fmi", [3, 2])
def test_paper_pressure_scenario_equals_predict(fmus, fmi):
    """The paper's experiment (175 bar on the lift's bore side, tilt held) into the lift's end stop."""
    sc = cp.scenarios.get("paper-fig4")
    u = Unit(fmus["pressure", fmi]).init(tilt_hold=True, load_mass=sc.crane.load_mass,
                                         lift_p_a_in=175e5, lift_p_b_in=0.0)
    got, stops = u.run([0.01] * 200)
    u.close()
    want, want_stops = _predicted(cp.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt=0.005, method="rk4"), 2)
    _assert_outputs(got, stops, want, want_stops)
    assert stops[-1, 0] == 1, "the lift reaches its upper stop"


@pytest.mark.parametrize("fmi", [3, 2])
def test_initialization_computes_the_state_at_rest(fmus, fmi):
    """Every levered actuator starts holding the crane: the chamber pressures of
    cranepredict.state_at_rest, and with the levers closed the crane does not move."""
    crane = dataclasses.replace(cp.Crane.patu655(), load_mass=350.0)
    rest = cp.state_at_rest(crane, 0.3, 0.25, extension=0.4)
    u = Unit(fmus["levers4", fmi]).init(load_mass=350.0, lift_stroke_start=0.3,
                                         tilt_stroke_start=0.25, extension_start=0.4)
    names = [f"{j}_p_{s}" for j in ("lift", "tilt", "slew", "extension") for s in "ab"]
    got = u.get(names)
    want = [getattr(rest, n) for n in names]
    np.testing.assert_allclose(got, want, rtol=1e-12)
    start = u.get()
    for _ in range(50):
        u.step(0.01)
    np.testing.assert_allclose(u.get()[:5], start[:5], rtol=0, atol=1e-6)
    u.close()


@pytest.mark.parametrize("fmi", [3, 2])
def test_outputs_during_initialization(fmus, fmi):
    """Outputs asked for in Initialization Mode are computed from what has been set so far."""
    u = Unit(fmus["levers2", fmi])
    if fmi == 3:
        u.fmu.enterInitializationMode(startTime=0.0)
    else:
        u.fmu.setupExperiment(startTime=0.0)
        u.fmu.enterInitializationMode()
    u.set(lift_stroke_start=0.3)
    during = u.get()
    u.fmu.exitInitializationMode()
    np.testing.assert_array_equal(u.get(), during)
    rest = cp.state_at_rest(cp.Crane.patu655(), 0.3, POSE["tilt_stroke"])
    assert during[3] == pytest.approx(0.3, abs=1e-12)
    assert during[5] == pytest.approx(rest.lift_p_a, rel=1e-12)
    u.close()


@pytest.mark.parametrize("fmi", [3, 2])
def test_all_four_levers_equal_predict(fmus, fmi):
    """Every actuator on its valve: lift lever open, slew lever half open, the others closed."""
    crane = cp.Crane.patu655()
    rest = cp.state_at_rest(crane, POSE["lift_stroke"], POSE["tilt_stroke"])
    inputs = cp.Inputs(lift=cp.Valve(u=1.0), tilt=cp.Valve(u=0.0), slew=cp.Valve(u=0.5),
                       extension=cp.Valve(u=0.0))
    u = Unit(fmus["levers4", fmi]).init(lift_lever=1.0, tilt_lever=0.0, slew_lever=0.5,
                                        extension_lever=0.0)
    got, stops = u.run([0.01] * 100)
    u.close()
    want, want_stops = _predicted(cp.predict(crane, rest, inputs, 1.0, dt=0.005, method="rk4"), 2)
    _assert_outputs(got, stops, want, want_stops)


@pytest.mark.parametrize("fmi", [3, 2])
def test_get_and_set_state_reproduce_a_run_exactly(fmus, fmi):
    u = Unit(fmus["levers2", fmi]).init()
    u.set(lift_lever=1.0)
    for _ in range(50):
        u.step(0.01)
    get_state = u.fmu.getFMUState if fmi == 3 else u.fmu.getFMUstate
    set_state = u.fmu.setFMUState if fmi == 3 else u.fmu.setFMUstate
    serialize = u.fmu.serializeFMUState if fmi == 3 else u.fmu.serializeFMUstate
    deserialize = u.fmu.deserializeFMUState if fmi == 3 else u.fmu.deSerializeFMUstate
    state = get_state()
    blob = serialize(state)
    t0 = u.t
    first, first_stops = u.run([0.01] * 100)
    u.set(lift_lever=-1.0, tilt_lever=0.7)   # the levers are part of the state
    u.run([0.01] * 30)
    set_state(state)
    u.t = t0
    again, again_stops = u.run([0.01] * 100)
    np.testing.assert_array_equal(again, first)
    np.testing.assert_array_equal(again_stops, first_stops)
    set_state(deserialize(bytes(blob)))
    u.t = t0
    third, _ = u.run([0.01] * 100)
    np.testing.assert_array_equal(third, first)
    u.close()


@pytest.mark.filterwarnings("ignore:Inputs.lift. holding the load")   # 450 kg: the boom sinks
@pytest.mark.parametrize("fmi", [3, 2])
def test_load_mass_is_tunable_while_stepping(fmus, fmi):
    """load_mass changed after 0.5 s: from then on the motion is the prediction of the heavier
    crane from the state at 0.5 s (the chambers as they were)."""
    sc = cp.scenarios.get("lever-open")
    u = Unit(fmus["levers2", fmi]).init(lift_lever=1.0, tilt_lever=0.0)
    u.run([0.01] * 50)
    u.set(load_mass=450.0)
    got, stops = u.run([0.01] * 100)
    u.close()
    first = cp.predict(sc.crane, sc.initial, sc.inputs, 0.5, dt=0.005, method="rk4")
    heavy = dataclasses.replace(sc.crane, load_mass=450.0)
    want, want_stops = _predicted(cp.predict(heavy, first.final_state, sc.inputs, 1.0, dt=0.005, method="rk4"), 2)
    _assert_outputs(got, stops, want, want_stops)
    light, _ = _predicted(cp.predict(sc.crane, sc.initial, sc.inputs, 1.5, dt=0.005, method="rk4"), 2)
    assert np.abs(got[-1, 2] - light[-1, 2]) > 1e-3   # the load made a difference


@pytest.mark.parametrize("fmi", [3, 2])
def test_two_instances_with_different_loads_do_not_interfere(fmus, fmi):
    def solo(load):
        u = Unit(fmus["levers2", fmi]).init(load_mass=load)
        u.set(lift_lever=1.0)
        rows, _ = u.run([0.01] * 100)
        u.close()
        return rows

    a = Unit(fmus["levers2", fmi], "a").init(load_mass=100.0)
    b = Unit(fmus["levers2", fmi], "b").init(load_mass=500.0)
    a.set(lift_lever=1.0)
    b.set(lift_lever=1.0)
    rows_a, rows_b = [a.get()], [b.get()]
    for _ in range(100):
        a.step(0.01)
        b.step(0.01)
        rows_a.append(a.get())
        rows_b.append(b.get())
    a.close()
    b.close()
    np.testing.assert_array_equal(np.array(rows_a), solo(100.0))
    np.testing.assert_array_equal(np.array(rows_b), solo(500.0))
    assert np.abs(np.array(rows_a)[:, 2] - np.array(rows_b)[:, 2]).max() > 1e-3


@pytest.mark.parametrize("fmi", [3, 2])
def test_a_step_that_is_not_a_multiple_of_the_internal_one(fmus, fmi):
    """0.004999999 s (shorter than the 5-ms step: one step each): the same grid as a prediction
    with that step, so equal to rounding."""
    h = 0.004999999
    sc = cp.scenarios.get("lever-open")
    u = Unit(fmus["levers2", fmi]).init(lift_lever=1.0)
    got, stops = u.run([h] * 400)
    u.close()
    want, want_stops = _predicted(cp.predict(sc.crane, sc.initial, sc.inputs, 400 * h, dt=h, method="rk4"), 1)
    _assert_outputs(got, stops, want, want_stops)


@pytest.mark.parametrize("fmi", [3, 2])
def test_random_communication_steps(fmus, fmi):
    """Communication steps drawn from [0.5, 25] ms: the FMU's step grid is theirs, each cut into
    steps of at most 5 ms, so it agrees with a fine prediction (0.1 ms) to the integrator's
    truncation error at 5 ms, not to rounding (docs/fmu.md)."""
    rng = random.Random(7)
    steps = [rng.uniform(0.0005, 0.025) for _ in range(150)]
    sc = cp.scenarios.get("lever-open")
    u = Unit(fmus["levers2", fmi]).init()
    u.set(lift_lever=1.0)
    got, _ = u.run(steps)
    u.close()
    # the scale: a 5-ms prediction's largest tip error against the 0.1-ms one over the 2 s
    fine = cp.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt=1e-4, method="rk4")
    coarse = cp.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt=0.005, method="rk4")
    scale = np.abs(coarse.tip - fine.tip[::50]).max()
    assert 1e-9 < scale < 1e-6, scale
    t = np.concatenate([[0.0], np.cumsum(steps)])
    for k in range(15, len(t), 15):
        ref = cp.predict(sc.crane, sc.initial, sc.inputs, float(t[k]), dt=1e-4, method="rk4")
        np.testing.assert_allclose(got[k, :3], ref.tip[-1], rtol=0, atol=scale)


@pytest.mark.parametrize("fmi", [3, 2])
def test_guard_outputs_equal_the_guard_on_a_prediction(fmus, fmi):
    """With a world: at each communication point the verdict of crane_guard on the future from
    the FMU's state under its inputs, as cranepredict's guard judges the same future (predicted
    from Trajectory.final_state, every 10 ms): the signal, the contact and stop times and the
    least clearance."""
    g = importlib.import_module("cranepredict.guard")
    sc = cp.scenarios.get("lever-open")
    shape = g._shape(sc.crane, None)
    values = {"margin": BEAM.margin, "reaction": g.DEFAULT_REACTION, "cycle": g.DEFAULT_CYCLE,
              "time_tolerance": g.DEFAULT_TIME_TOLERANCE,
              "clearance_tolerance": g.DEFAULT_CLEARANCE_TOLERANCE}
    u = Unit(fmus["guard", fmi]).init(lift_lever=1.0, tilt_lever=0.0)
    names = ["time_to_contact", "min_clearance", "stop_latest"]
    signals = []
    for k in range(101):
        if k % 25 == 0:
            got = u.get(names)
            vr = [u.vr["guard_signal"]]
            signal = (u.fmu.getInt32(vr) if fmi == 3 else u.fmu.getInteger(vr))[0]
            state = sc.initial if k == 0 else \
                cp.predict(sc.crane, sc.initial, sc.inputs, 0.01 * k, dt=0.005, method="rk4").final_state
            future = cp.predict_many(sc.crane, [state], [sc.inputs], 2.0, dt=0.005, method="rk4",
                                     sample_every=2)[0]
            res, clearance = g._judge(sc.crane, BEAM, g._samples(future), shape, values)
            assert res.contact and res.signal == 1   # WARN by the freezing stop
            assert signal == 2                         # the FMU: STOP for any predicted contact
            np.testing.assert_allclose(got, [res.t, clearance.min(), res.stop_latest], rtol=0,
                                       atol=1e-9)
            signals.append(signal)
        u.step(0.01)
    u.close()
    assert signals == [2] * 5   # the contact comes closer, 1.8 s -> 0.8 s ahead


@pytest.mark.parametrize("fmi", [3, 2])
def test_sources_build_the_same_fmu(fmus, fmi, tmp_path):
    """An importer compiles the FMU from sources/ by its build description (FMI 3) or the
    SourceFiles of the model description (FMI 2) alone: the binary it makes runs as the shipped."""
    import xml.etree.ElementTree as ET
    import zipfile

    cc = next(shutil.which(c) for c in ("cc", "gcc", "clang") if shutil.which(c))
    fmu = fmus["levers2", fmi]
    root = tmp_path / "fmu"
    with zipfile.ZipFile(fmu) as z:
        z.extractall(root)
    if fmi == 3:
        files = [e.get("name") for e in
                 ET.parse(root / "sources" / "buildDescription.xml").iter("SourceFile")]
    else:
        files = [e.get("name") for e in ET.parse(root / "modelDescription.xml").iter("File")]
    (binary,) = list((root / "binaries").rglob("crane.so"))
    binary.unlink()
    headers = Path(fmpy.__file__).parent / "c-code"
    subprocess.run([cc, "-shared", "-fPIC", "-std=c99", f"-I{headers}",
                    f"-I{root / 'sources'}", "-o", str(binary)] +
                   [str(root / "sources" / f) for f in files] + ["-lm"], check=True)
    rebuilt = tmp_path / "rebuilt.fmu"
    with zipfile.ZipFile(rebuilt, "w") as z:
        for p in sorted(root.rglob("*")):
            if p.is_file():
                z.write(p, p.relative_to(root).as_posix())
    runs = []
    for path in (fmu, rebuilt):
        u = Unit(path).init(lift_lever=1.0)
        runs.append(u.run([0.01] * 50)[0])
        u.close()
    # the same bits on x86-64; a target whose compiler contracts a * b + c into FMA at -O2 only
    # (aarch64) differs by rounding
    np.testing.assert_allclose(runs[1], runs[0], rtol=1e-12, atol=1e-9)


def test_errors_go_through_the_logger_and_never_abort(fmus):
    messages = []

    def log(env, status, category, message):
        messages.append(message.decode())

    from fmpy.fmi3 import fmi3LogMessageCallback
    u = Unit(fmus["levers2", 3], log=fmi3LogMessageCallback(log)).init()
    with pytest.raises(Exception):
        u.set(lift_lever=1.5)
    assert any("lift_lever must be in [-1, 1], got 1.5" in m for m in messages), messages
    with pytest.raises(Exception):
        u.step(0.0)
    assert any("communication step must be > 0" in m for m in messages), messages
    with pytest.raises(Exception):
        u.set(lift_stroke_start=0.2)
    assert any("cannot be set after the initialization" in m for m in messages), messages
    u.set(lift_lever=0.5)   # still alive and stepping
    u.step(0.01)
    u.close()


def test_initial_pose_out_of_range_is_an_error_not_an_abort(fmus):
    messages = []

    def log(env, status, category, message):
        messages.append(message.decode())

    from fmpy.fmi3 import fmi3LogMessageCallback
    u = Unit(fmus["levers2", 3], log=fmi3LogMessageCallback(log))
    with pytest.raises(Exception):
        u.init(lift_stroke_start=5.0)
    assert any("lift_stroke_start" in m and "stroke" in m for m in messages), messages
    u.fmu.freeInstance()


def test_cli_writes_an_fmu(tmp_path):
    out = tmp_path / "c.fmu"
    r = subprocess.run([sys.executable, "-m", "cranepredict.cli", "fmu", "--fmi", "2",
                        "--levers", "lift", "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert validate_fmu(str(out)) == []
    md = read_model_description(str(out))
    assert [v.name for v in md.modelVariables if v.causality == "input"] == ["lift_lever"]
    r = subprocess.run([sys.executable, "-m", "cranepredict.cli", "fmu", "--levers", "boom",
                        "-o", str(tmp_path / "x.fmu")], capture_output=True, text=True)
    assert r.returncode == 2 and "'boom' is not a joint" in r.stderr
    r = subprocess.run([sys.executable, "-m", "cranepredict.cli", "fmu", "--world", "wall",
                        "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    names = [v.name for v in read_model_description(str(out)).modelVariables]
    assert {"guard_signal", "time_to_contact", "min_clearance", "stop_latest",
            "guard_horizon"} <= set(names)


def test_bad_arguments_are_named():
    crane = cp.Crane.patu655()
    with pytest.raises(ValueError, match="fmi must be 3 or 2"):
        export_fmu(crane, "x.fmu", fmi=1)
    with pytest.raises(ValueError, match="drive must be one of"):
        export_fmu(crane, "x.fmu", drive="electric")
    with pytest.raises(ValueError, match="step must be > 0"):
        export_fmu(crane, "x.fmu", step=0.0)
    with pytest.raises(ValueError, match="start: 'boom' is not one of"):
        export_fmu(crane, "x.fmu", start={"boom": 1.0})
    with pytest.raises(TypeError, match="crane must be a cranepredict.Crane"):
        export_fmu("patu655", "x.fmu")
    with pytest.raises(TypeError, match="world must be a cranepredict.World"):
        export_fmu(crane, "x.fmu", world="wall")
    with pytest.raises(ValueError, match="guard_horizon must be > 0"):
        export_fmu(crane, "x.fmu", world=BEAM, guard_horizon=-1.0)

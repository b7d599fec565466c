"""Uncertainty sweeps (cranepredict.uncertainty, docs/sweep.md): the same table in-process and on a
two-worker Dask LocalCluster, resuming an interrupted study without recomputing its chunks, each
sample's verdict against the guard run on a Crane built with the sample's values, the margin the
summary recommends checked by running the study with it, and bad study files."""

from __future__ import annotations

import dataclasses
import json
import math
import sys

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import uncertainty
from cranepredict.cli import main

STUDY = cp.studies.get("power-line-load")


def small(samples: int = 12, chunk: int = 4, **changes) -> uncertainty.Study:
    return dataclasses.replace(STUDY, samples=samples, chunk=chunk, **changes)


def same_tables(a: dict, b: dict) -> bool:
    return set(a) == set(b) and all(np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f")
                                    for k in a)


def test_example_ships():
    assert "power-line-load" in cp.studies.names()
    assert STUDY.world.name == "power-line" and STUDY.parameters == ("load_mass",)
    assert STUDY.crane.load_mass == 200.0


def test_local_cluster_and_in_process_give_the_same_table():
    distributed = pytest.importorskip("distributed")
    study = small(12, 3)
    here = cp.sweep(study, scheduler="in-process")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = cp.sweep(study, scheduler=client)
        assert len(client.scheduler_info()["workers"]) == 2
        by_address = cp.sweep(study, scheduler=cluster.scheduler_address)   # as --scheduler ADDR
    assert "Dask" in there.where and here.where == "in this process"
    assert cluster.scheduler_address in by_address.where
    assert same_tables(here.table, there.table) and same_tables(here.table, by_address.table)
    assert here.summary == there.summary


def test_chunks_are_drawn_from_their_own_seeds():
    """Chunk i's samples depend on the seed and i only: a longer study starts with a shorter
    one's rows; another seed draws other loads."""
    short = cp.sweep(small(8, 4), scheduler="in-process")
    longer = cp.sweep(small(12, 4), scheduler="in-process")
    assert same_tables(short.table, {k: v[:8] for k, v in longer.table.items()})
    other = cp.sweep(small(8, 4, seed=STUDY.seed + 1), scheduler="in-process")
    assert not np.array_equal(other.table["draws"], short.table["draws"])
    # the draws are the file's distribution: load within +-20 % of 200 kg
    loads = longer.values("load_mass")
    assert np.all((loads >= 160.0) & (loads <= 240.0)) and np.ptp(loads) > 20.0


def test_interrupted_study_resumes_without_recomputing(tmp_path, monkeypatch):
    study = small(12, 3)
    real = uncertainty.run_chunk
    calls = []

    def interrupted(st, nominal, index, threads=1):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(index)
        return real(st, nominal, index, threads)

    monkeypatch.setattr(uncertainty, "run_chunk", interrupted)
    with pytest.raises(KeyboardInterrupt):
        cp.sweep(study, out=tmp_path, scheduler="in-process")
    written = sorted(p.name for p in tmp_path.glob("chunk-*.npz"))
    assert written == [f"chunk-{i:05d}.npz" for i in calls] and len(written) == 2
    (tmp_path / ".chunk-00003.npz.tmp").write_bytes(b"half a chunk")   # a write cut short

    def counted(st, nominal, index, threads=1):
        calls.append(index)
        return real(st, nominal, index, threads)

    monkeypatch.setattr(uncertainty, "run_chunk", counted)
    resumed = cp.sweep(study, out=tmp_path, scheduler="in-process")
    assert calls == [0, 1, 2, 3] and resumed.computed_chunks == 2
    monkeypatch.setattr(uncertainty, "run_chunk", real)
    assert same_tables(resumed.table, cp.sweep(study, scheduler="in-process").table)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["samples"] == 12
    # a folder of another study is refused, naming what differs
    with pytest.raises(ValueError, match="seed"):
        cp.sweep(study, seed=1, out=tmp_path, scheduler="in-process")


def test_each_sample_is_the_guard_of_a_crane_with_its_values():
    """A sample's verdict (signal, latest stop time, first contact) is cp.guard's on a Crane built
    with its load, judged against the world's margin; the twin's decision misses exactly the
    samples whose own latest stop time is earlier than the twin's."""
    result = cp.sweep(small(6, 6), scheduler="in-process")
    t, study = result.table, result.study
    loads = result.values("load_mass")
    nominal = cp.guard(study.crane, study.world, study.cases[0].initial, study.cases[0].inputs,
                       study.horizon)
    assert nominal.signal == "WARN"
    for k in (int(np.argmin(loads)), int(np.argmax(loads))):
        v = cp.guard(study.crane.with_load(float(loads[k])), study.world, study.cases[0].initial,
                     study.cases[0].inputs, study.horizon)
        assert uncertainty.SIGNALS[t["signal"][k]] == v.signal
        assert t["latest"][k] == pytest.approx(v.stop.latest, abs=1e-12)
        j = study.world.names.index(v.contact.obstacle)
        assert t["t_contact"][k, j] == pytest.approx(v.contact.t, abs=2e-4)
        assert min(t["clearance"][k]) == pytest.approx(min(v.clearance.values()), abs=2e-3)
        assert bool(t["missed"][k].any()) == (nominal.stop.latest > v.stop.latest)
    # physics: a lighter load rises faster, so it needs an earlier stop
    order = np.argsort(loads)
    assert np.all(np.diff(t["latest"][order]) >= 0)


def test_recommended_margin_meets_the_target():
    """Run again with the guard margin the summary recommends: the contacts missed (now by the
    decisions' own simulation) are at most the target; two resolution steps less miss more (the
    recommendation is the bisection's bound rounded up to MARGIN_RESOLUTION, so one step less can
    still meet the target: 1 cm less did with ROS34PW2's trajectories, 1.5 cm less did not)."""
    study = small(20, 10, target=0.1)
    first = cp.sweep(study, scheduler="in-process").summary
    assert first.miss_rate > study.target and math.isfinite(first.margin_for_target)
    at = cp.sweep(dataclasses.replace(study, margin=first.margin_for_target),
                  scheduler="in-process").summary
    assert at.miss_rate <= study.target
    below = cp.sweep(dataclasses.replace(
        study, margin=first.margin_for_target - 2 * uncertainty.MARGIN_RESOLUTION),
        scheduler="in-process").summary
    assert below.miss_rate > study.target


def test_plot(tmp_path):
    pytest.importorskip("matplotlib")
    result = cp.sweep(small(8, 4), scheduler="in-process")
    path = result.plot(tmp_path / "sweep.png")
    assert path.stat().st_size > 10_000


def test_cli(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["sweep", "power-line-load", "--samples", "4", "--in-process", "--out", str(out),
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["samples"] == 4 and d["computed_chunks"] == 1 and d["where"] == "in this process"
    assert [o["name"] for o in d["obstacles"]] == list(STUDY.world.names)
    assert main(["sweep", "power-line-load", "--samples", "4", "--in-process", "--out",
                 str(out)]) == 0
    assert "1 chunks were already in" in capsys.readouterr().out
    assert main(["sweep", "no-such-study", "--in-process"]) == 2
    assert "not an example study (power-line-load)" in capsys.readouterr().err
    assert main(["sweep", "power-line-load", "--samples", "0", "--in-process"]) == 2
    assert "samples must be an int in [1, " in capsys.readouterr().err


BASE = cp.studies.text("power-line-load")


@pytest.mark.parametrize("change, kind, message", [
    (("samples = 2000", "samples = 0"), ValueError, r"samples must be an int in \[1, "),
    (("chunk = 100", "chunk = 1.5"), ValueError, r"chunk must be an int in \[1, 100,000\]"),
    (("target = 0.01 ", "target = 1.5 "), ValueError, r"target must be in \(0, 1\)"),
    (("horizon = 2.0", "horizon = -1"), ValueError, r"horizon must be in \(0, inf\)"),
    (("reaction = 0.2", "reaction = -0.1"), ValueError, r"reaction must be in \[0, inf\)"),
    (("cycle = 0.01", "cycle = 0.01\nmargins = 2"), ValueError, r"unknown field\(s\) guard.margins"),
    (("world = \"power-line\"", "world = \"nowhere\""), ValueError,
     r"world 'nowhere' is neither a world file .* \(building-edge, cab, power-line, wall\)"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "load_mass = { uniform = [0.2, -0.2], relative = true }"), ValueError,
     r"uncertain.load_mass.uniform = \[low, high\] must have low <= high"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "load_mass = { normal = [0.0, -1.0] }"), ValueError, r"sd >= 0"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "load_mass = { uniform = [-1.5, 0.2], relative = true }"), ValueError,
     r"a relative draw must stay above -1"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "load_mass = { uniform = [-50.0, 100.0] }"), ValueError,
     r"ends give an invalid future \(case 'lift at 175 bar', load_mass = -50\): future \d+ \(vary\): "
     r"load_mass must be >= 0"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "\"state.lift_stroke\" = { uniform = [-0.5, 0.0] }"), ValueError,
     r"state.lift_stroke offset -0.5\): .*State.lift_stroke must be in"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "\"geometry.tip_distance\" = { uniform = [-0.1, 0.1] }"), ValueError,
     r"neither a crane field a sweep can vary"),
    (("load_mass = { uniform = [-0.2, 0.2], relative = true }",
      "load_mass = { beta = [1, 2] }"), ValueError,
     r"uncertain.load_mass must have one of uniform = \[low, high\] or normal"),
    (("seed = 20261202", "seed = 1\nsamplez = 3"), ValueError, r"unknown field\(s\) samplez"),
    (("inputs.tilt = { hold = true }", ""), ValueError, r"case\[0\].inputs must have the tables lift"),
])
def test_bad_study_names_field_and_range(change, kind, message):
    old, new = change
    assert old in BASE
    with pytest.raises(kind, match=message):
        uncertainty.Study.from_toml_string(BASE.replace(old, new))


def test_study_file_next_to_its_world(tmp_path):
    """A study file names a world file next to it (and the file's errors name the file)."""
    (tmp_path / "site.toml").write_text('name = "site"\nmargin = 0.3\n[[obstacle]]\nname = "wall"\n'
                                        'kind = "box"\ncentre = [5.75, 0.0, 0.3]\n'
                                        'size = [0.3, 10.0, 3.0]\n')
    path = tmp_path / "study.toml"
    path.write_text(BASE.replace('world = "power-line"', 'world = "site.toml"')
                    .replace("samples = 2000", "samples = 4"))
    result = cp.sweep(str(path), scheduler="in-process")
    assert result.study.world.names == ("wall",) and len(result.table["sample"]) == 4
    path.write_text(BASE.replace("samples = 2000", "samples = -4"))
    with pytest.raises(ValueError, match=f"{path}: samples must be"):
        cp.sweep(str(path), scheduler="in-process")


def test_without_dask_the_default_runs_in_process(monkeypatch):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)   # import fails as if absent
    assert not uncertainty.has_dask()
    result = cp.sweep(small(4, 4))
    assert result.where == "in this process"


def test_progress_bar(capsys):
    cp.sweep(small(8, 4), scheduler="in-process", progress=True)
    err = capsys.readouterr().err
    assert "2/2 chunks" in err and "futures/s" in err

"""Shared fixtures: the PATU 655 crane and a generator of random scenarios."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cranepredict as cp


@pytest.fixture(scope="session")
def crane() -> cp.Crane:
    return cp.Crane.patu655()


def frictionless(crane: cp.Crane, gravity: float | None = None) -> cp.Crane:
    """The crane with every friction coefficient zero (energy is then conserved)."""
    zero = cp.Friction(coulomb=0.0, static=0.0, viscous=0.0, stribeck_velocity=0.005,
                       factor=1.0)
    c = dataclasses.replace(
        crane,
        lift_cylinder=dataclasses.replace(crane.lift_cylinder, friction=zero),
        tilt_cylinder=dataclasses.replace(crane.tilt_cylinder, friction=zero))
    return c if gravity is None else dataclasses.replace(c, gravity=gravity)


def random_drive(rng: np.random.Generator, horizon: float):
    kind = rng.integers(0, 3)
    if kind == 0:
        return cp.Hold()
    if kind == 1:
        return cp.Pressure(p_a=rng.uniform(0, 200e5), p_b=rng.uniform(0, 200e5))
    n = int(rng.integers(2, 8))
    t = np.concatenate([[0.0], np.sort(rng.uniform(0, horizon, n - 2)), [horizon]])
    t = np.unique(t)
    return cp.PressureSeries(t=t, p_a=rng.uniform(0, 200e5, t.size), p_b=rng.uniform(0, 200e5, t.size))


def random_case(rng: np.random.Generator, crane: cp.Crane, horizon: float = 2.0):
    """(crane, initial, inputs): loads 0-500 kg, strokes across their ranges, slew, extension."""
    c = crane.with_load(float(rng.uniform(0, 500)))
    lc, tc, g = c.lift_cylinder, c.tilt_cylinder, c.geometry
    initial = cp.State(lift_stroke=float(rng.uniform(lc.stroke_min, lc.stroke_max)),
                       tilt_stroke=float(rng.uniform(tc.stroke_min, tc.stroke_max)),
                       slew=float(rng.uniform(-np.pi, np.pi)),
                       extension=float(rng.uniform(g.extension_min, g.extension_max)))
    inputs = cp.Inputs(lift=random_drive(rng, horizon), tilt=random_drive(rng, horizon))
    return c, initial, inputs

"""Shared fixtures: the PATU 655 crane, a frictionless variant and the random scenarios."""

from __future__ import annotations

import dataclasses

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


# The random scenarios live in the package (tools/dt_study.py uses them too); the tests import
# them from here.
random_case = cp.scenarios.random_case
random_drive = cp.scenarios.random_drive

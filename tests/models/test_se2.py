"""SE(2): group laws, matrix form (000 Eq. 1), wrapping, vectorized twins."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from swarmproof.models.errors import UsageError
from swarmproof.models.se2 import (SE2, apply_many, compose_many, inverse_many, relative_many,
                                   wrap_angle)

coord = st.floats(-100, 100, allow_nan=False)
angle = st.floats(-10, 10, allow_nan=False)
poses = st.builds(SE2, coord, coord, angle)


@given(poses, poses, poses)
def test_associative(a, b, c):
    assert ((a @ b) @ c).isclose(a @ (b @ c), pos_tol=1e-7, ang_tol=1e-9)


@given(poses)
def test_inverse_and_identity(a):
    assert (a @ a.inverse()).isclose(SE2.identity(), pos_tol=1e-9, ang_tol=1e-12)
    assert (a.inverse() @ a).isclose(SE2.identity(), pos_tol=1e-9, ang_tol=1e-12)
    assert (SE2.identity() @ a).isclose(a, 0, 0)


@given(poses, poses)
def test_matrix_is_homomorphism(a, b):
    np.testing.assert_allclose((a @ b).matrix(), a.matrix() @ b.matrix(), atol=1e-9)
    assert SE2.from_matrix(a.matrix()).isclose(a, 1e-9, 1e-12)


@given(poses, poses)
def test_vectorized_twins_agree(a, b):
    np.testing.assert_allclose(compose_many([a.as_array()], [b.as_array()])[0, :2],
                               (a @ b).as_array()[:2], atol=1e-9)
    assert abs(wrap_angle(compose_many([a.as_array()], [b.as_array()])[0, 2] - (a @ b).theta)) < 1e-12
    np.testing.assert_allclose(inverse_many([a.as_array()])[0, :2], a.inverse().as_array()[:2], atol=1e-9)
    rel = relative_many(a.as_array(), [b.as_array()])[0]
    assert SE2.from_array(rel).isclose(b.relative_to(a), 1e-8, 1e-9)
    np.testing.assert_allclose(apply_many(a.as_array(), [[b.x, b.y]])[0], a.apply([b.x, b.y]), atol=1e-9)


@given(st.floats(-1e6, 1e6, allow_nan=False))
def test_wrap_range(t):
    w = wrap_angle(t)
    assert -math.pi <= w < math.pi
    assert math.isclose(math.cos(w), math.cos(t), abs_tol=1e-6)


@pytest.mark.parametrize("args, match", [
    ((float("nan"), 0, 0), r"x=nan must be a finite number"),
    ((0, float("inf"), 0), r"y=inf must be a finite number"),
    ((0, 0, "a"), r"theta='a' must be a finite number"),
], ids=["nan-x", "inf-y", "str-theta"])
def test_invalid(args, match):
    with pytest.raises(UsageError, match=match):
        SE2(*args)


def test_from_matrix_rejects_non_rigid():
    with pytest.raises(UsageError, match="not a rigid transform"):
        SE2.from_matrix(np.diag([2.0, 1.0, 1.0]))

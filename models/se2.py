"""Rigid body transformations of the plane, SE(2).

A pose ``(x, y, theta)`` and a transform are the same object: the pose of a
frame B expressed in frame A *is* the transform that maps B-coordinates to
A-coordinates.  The homogeneous matrix is that of 000 Eq. (1)::

    T = [[cos t, -sin t, x],
         [sin t,  cos t, y],
         [0,      0,     1]]

Composition follows Definition 3 of 001 (endpoint transformation of a path
``u -e1-> w -e2-> z`` is ``T(e1) @ T(e2)``): ``a @ b`` is "b expressed in the
frame of a".  Angles are always wrapped into ``[-pi, pi)``.

Two APIs share one implementation of the formulas:

* :class:`SE2`, an immutable scalar value for model code (lattice graphs,
  proofs, file formats);
* ``compose_many`` / ``inverse_many`` / ``relative_many`` / ``apply_many``
  over ``(n, 3)`` numpy arrays, for the simulation engine's hot path.

References
----------
000_3ad33c5b62f11d5f.txt (Song & O'Kane, ICRA 2014), Sec. III-A, Eq. (1).
001_7a4e517b856331bc.txt (Song & O'Kane, IROS 2016), Defs. 1-3.

Examples
--------
>>> a = SE2(1.0, 0.0, math.pi / 2)
>>> b = SE2(1.0, 0.0, 0.0)
>>> (a @ b).isclose(SE2(1.0, 1.0, math.pi / 2))
True
>>> (a @ a.inverse()).isclose(SE2.identity())
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable

import numpy as np

from .errors import UsageError, check_finite

__all__ = [
    "SE2",
    "wrap_angle",
    "angle_diff",
    "compose_many",
    "inverse_many",
    "relative_many",
    "apply_many",
    "DEFAULT_POS_TOL",
    "DEFAULT_ANG_TOL",
]

#: Default absolute tolerance for positions (same unit as the lattice edges).
DEFAULT_POS_TOL = 1e-9
#: Default absolute tolerance for angles, in radians.
DEFAULT_ANG_TOL = 1e-9

_TWO_PI = 2.0 * math.pi


def wrap_angle(theta):
    """Wrap an angle (or an array of angles) into ``[-pi, pi)``.

    >>> wrap_angle(3 * math.pi / 2) == -math.pi / 2
    True
    >>> wrap_angle(math.pi)
    -3.141592653589793
    """
    if isinstance(theta, np.ndarray):
        return np.mod(theta + math.pi, _TWO_PI) - math.pi
    w = math.fmod(theta + math.pi, _TWO_PI)
    if w < 0:
        w += _TWO_PI
    return w - math.pi


def angle_diff(a, b):
    """Signed smallest difference ``a - b`` wrapped into ``[-pi, pi)``.

    >>> round(angle_diff(math.radians(350), math.radians(10)), 12) == round(math.radians(-20), 12)
    True
    """
    return wrap_angle(a - b)


@dataclass(frozen=True, slots=True)
class SE2:
    """An element of SE(2): a planar pose or rigid transform ``(x, y, theta)``.

    Parameters
    ----------
    x, y : float
        Translation.
    theta : float
        Rotation in radians; stored wrapped into ``[-pi, pi)``.

    Raises
    ------
    UsageError
        If a component is not a finite real number.

    Examples
    --------
    >>> SE2(0, 0, 2 * math.pi).theta
    0.0
    >>> SE2(float("inf"), 0, 0)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: x=inf must be a finite number; fix: give a finite real number
    """

    x: float
    y: float
    theta: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "x", check_finite("x", self.x))
        object.__setattr__(self, "y", check_finite("y", self.y))
        object.__setattr__(self, "theta", wrap_angle(check_finite("theta", self.theta)))

    # -- constructors -------------------------------------------------
    @staticmethod
    def identity() -> "SE2":
        """The identity transform."""
        return SE2(0.0, 0.0, 0.0)

    @staticmethod
    def from_matrix(m) -> "SE2":
        """From a 3x3 homogeneous matrix (000 Eq. 1); the rotation block must be a rotation.

        >>> SE2.from_matrix(SE2(1, 2, 0.5).matrix()).isclose(SE2(1, 2, 0.5))
        True
        """
        m = np.asarray(m, dtype=float)
        if m.shape != (3, 3):
            raise UsageError(f"matrix shape={m.shape!r} must be (3, 3)")
        r = m[:2, :2]
        if not (np.allclose(r.T @ r, np.eye(2), atol=1e-9) and np.linalg.det(r) > 0
                and np.allclose(m[2], [0, 0, 1], atol=1e-12)):
            raise UsageError("matrix is not a rigid transform (rotation block not orthonormal "
                             "with det +1, or last row not [0, 0, 1])")
        return SE2(float(m[0, 2]), float(m[1, 2]), math.atan2(m[1, 0], m[0, 0]))

    @staticmethod
    def from_array(a) -> "SE2":
        """From any length-3 sequence ``[x, y, theta]``."""
        return SE2(float(a[0]), float(a[1]), float(a[2]))

    # -- group operations ----------------------------------------------
    def __matmul__(self, other: "SE2") -> "SE2":
        """Composition ``self @ other``: ``other`` expressed in the frame of ``self``'s parent."""
        if not isinstance(other, SE2):
            return NotImplemented
        c, s = math.cos(self.theta), math.sin(self.theta)
        return SE2(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            self.theta + other.theta,
        )

    def compose(self, other: "SE2") -> "SE2":
        """Same as ``self @ other``."""
        return self @ other

    def inverse(self) -> "SE2":
        """The inverse transform.

        >>> SE2(1, 0, math.pi / 2).inverse().isclose(SE2(0, 1, -math.pi / 2))
        True
        """
        c, s = math.cos(self.theta), math.sin(self.theta)
        return SE2(-c * self.x - s * self.y, s * self.x - c * self.y, -self.theta)

    def apply(self, points):
        """Map points from this frame into the parent frame.

        Parameters
        ----------
        points : array_like, shape (2,) or (n, 2)

        Returns
        -------
        numpy.ndarray of the same shape.

        >>> SE2(1, 0, math.pi / 2).apply([1.0, 0.0]).round(12).tolist()
        [1.0, 1.0]
        """
        p = np.asarray(points, dtype=float)
        c, s = math.cos(self.theta), math.sin(self.theta)
        rot = np.array([[c, -s], [s, c]])
        return p @ rot.T + np.array([self.x, self.y])

    def relative_to(self, frame: "SE2") -> "SE2":
        """This pose expressed in the body frame of ``frame``: ``frame.inverse() @ self``."""
        return frame.inverse() @ self

    # -- views ----------------------------------------------------------
    def matrix(self) -> np.ndarray:
        """The 3x3 homogeneous matrix of 000 Eq. (1)."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return np.array([[c, -s, self.x], [s, c, self.y], [0.0, 0.0, 1.0]])

    def as_array(self) -> np.ndarray:
        """``numpy.array([x, y, theta])``."""
        return np.array([self.x, self.y, self.theta])

    def as_tuple(self) -> tuple[float, float, float]:
        return (self.x, self.y, self.theta)

    @property
    def position(self) -> np.ndarray:
        """The translation part ``[x, y]`` (the "endpoint position" of 001 Def. 3)."""
        return np.array([self.x, self.y])

    def norm(self) -> float:
        """Length of the translation part."""
        return math.hypot(self.x, self.y)

    # -- comparison -----------------------------------------------------
    def isclose(self, other: "SE2", pos_tol: float = DEFAULT_POS_TOL,
                ang_tol: float = DEFAULT_ANG_TOL) -> bool:
        """Equal within explicit absolute tolerances (angles compared on the circle).

        >>> SE2(0, 0, math.pi - 1e-12).isclose(SE2(0, 0, -math.pi))
        True
        """
        return (abs(self.x - other.x) <= pos_tol and abs(self.y - other.y) <= pos_tol
                and abs(angle_diff(self.theta, other.theta)) <= ang_tol)

    def __repr__(self) -> str:
        return f"SE2(x={self.x:.6g}, y={self.y:.6g}, theta={math.degrees(self.theta):.6g}deg)"


# ----------------------------------------------------------------------
# Vectorized forms over (n, 3) arrays of [x, y, theta]: the same formulas.
# ----------------------------------------------------------------------

def _as_poses(a, name: str) -> np.ndarray:
    arr = np.asarray(a, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise UsageError(f"{name} shape={arr.shape!r} must be (n, 3) rows of [x, y, theta]")
    return arr


def compose_many(a, b) -> np.ndarray:
    """Row-wise ``a[i] @ b[i]`` (broadcasting a single row is allowed).

    >>> compose_many([[1, 0, math.pi / 2]], [[1, 0, 0]]).round(12).tolist()
    [[1.0, 1.0, 1.570796326795]]
    """
    a = _as_poses(np.atleast_2d(a), "a")
    b = _as_poses(np.atleast_2d(b), "b")
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[:, 0] = a[:, 0] + c * b[:, 0] - s * b[:, 1]
    out[:, 1] = a[:, 1] + s * b[:, 0] + c * b[:, 1]
    out[:, 2] = wrap_angle(a[:, 2] + b[:, 2])
    return out


def inverse_many(a) -> np.ndarray:
    """Row-wise inverse."""
    a = _as_poses(np.atleast_2d(a), "a")
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    out = np.empty_like(a)
    out[:, 0] = -c * a[:, 0] - s * a[:, 1]
    out[:, 1] = s * a[:, 0] - c * a[:, 1]
    out[:, 2] = wrap_angle(-a[:, 2])
    return out


def relative_many(frame, poses) -> np.ndarray:
    """Poses expressed in the body frame ``frame`` (one row), i.e. ``frame^-1 @ poses[i]``.

    This is what a robot *senses*: neighbors' poses in its own body frame.

    >>> relative_many([1, 1, math.pi / 2], [[1, 2, math.pi / 2]]).round(12).tolist()
    [[1.0, 0.0, 0.0]]
    """
    f = np.asarray(frame, dtype=float).reshape(1, 3)
    p = _as_poses(np.atleast_2d(poses), "poses")
    c, s = math.cos(f[0, 2]), math.sin(f[0, 2])
    dx = p[:, 0] - f[0, 0]
    dy = p[:, 1] - f[0, 1]
    out = np.empty_like(p)
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = wrap_angle(p[:, 2] - f[0, 2])
    return out


def apply_many(frame, points) -> np.ndarray:
    """Map ``(n, 2)`` points from the body frame ``frame`` (one row) into its parent frame."""
    f = np.asarray(frame, dtype=float).reshape(3)
    p = np.atleast_2d(np.asarray(points, dtype=float))
    c, s = math.cos(f[2]), math.sin(f[2])
    return np.column_stack((f[0] + c * p[:, 0] - s * p[:, 1], f[1] + s * p[:, 0] + c * p[:, 1]))


def as_se2_list(rows: Iterable) -> list[SE2]:
    """Convert rows of ``[x, y, theta]`` to a list of :class:`SE2`."""
    return [SE2.from_array(r) for r in rows]

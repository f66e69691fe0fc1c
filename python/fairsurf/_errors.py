"""The exceptions fairsurf raises (the native module raises these classes)."""

from __future__ import annotations

__all__ = ["FairsurfError", "SceneError", "SolveError", "UnverifiedError", "ExportError"]


class FairsurfError(Exception):
    """Base class of fairsurf's own errors (files raise ``OSError``)."""


class SceneError(FairsurfError, ValueError):
    """The scene is not valid.

    ``path`` is the JSON path of the offending value, e.g.
    ``surface.control_points[3][2]`` ("" for the whole document); the message
    starts with it.
    """

    path: str = ""


class SolveError(FairsurfError):
    """The solver refused the problem: too large for the memory limit, a
    singular or dependent system, a cancelled solve."""


class UnverifiedError(SolveError):
    """The answer failed the independent check on the written control net:
    double precision cannot hold this minimizer at this degree (use a lower
    degree or a B-spline surface)."""


class ExportError(FairsurfError, ValueError):
    """The surface cannot be written in the asked format (nothing was
    written)."""

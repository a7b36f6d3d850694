"""Exceptions raised for invalid input."""

from __future__ import annotations


class ParameterError(ValueError):
    """A parameter, option or input file is invalid.

    The message always names the parameter, the offending value and what is
    allowed, so that it can be shown to a user as it is.
    """

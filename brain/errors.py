"""Errors raised by the brain: one root and specific subclasses."""

from __future__ import annotations


class BrainError(Exception):
    """Root of every error raised by ``brain``."""


class SettingsError(BrainError, ValueError):
    """A settings file or override that names an unknown setting or a bad value."""

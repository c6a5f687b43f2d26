"""Errors raised by the brain: one root and specific subclasses."""

from __future__ import annotations


class BrainError(Exception):
    """Root of every error raised by ``brain``."""


class SettingsError(BrainError, ValueError):
    """A settings file or override that names an unknown setting or a bad value."""


class StateError(BrainError, ValueError):
    """A ``state`` the brain cannot follow: an item of the scene missing from it, neither
    resting nor held, held by an agent it does not list, or resting at an unknown place."""

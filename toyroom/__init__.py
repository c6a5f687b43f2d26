"""toyroom, the application: what a user runs, on top of the libraries (``protocol``,
``bridge``, ``brain``, ``sim2d``), which never import it.

- :mod:`.cli`: the ``toyroom`` command line, ``toyroom run`` and its live table, ``toyroom doctor``;
- :mod:`.evaluation`: ``toyroom eval``: generated episodes, runs, metrics, reports, Ray;
- :mod:`.fitting`: ``toyroom fit``: the model's parameters fitted to recordings (the one room
  that imports the brain: it replays the model in-process);
- :mod:`.play` and :mod:`.rating`: the study pages (``toyroom play``, ``toyroom rate``);
- :mod:`.view`: the meshcat live view (``toyroom view``).

``toyroom`` starts the engine and the brain as processes and meets them on the wire.
"""

from typing import Any

__all__ = ["RunConfig", "build_parser", "main", "run_doctor"]


def __getattr__(name: str) -> Any:
    """The command line's names, imported when first used (``import toyroom.view`` need not
    load the whole command line)."""
    if name in __all__:
        from . import cli

        return getattr(cli, name)
    raise AttributeError(f"module 'toyroom' has no attribute {name!r}")

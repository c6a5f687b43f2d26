"""The C# SDK and its sample engine, built with Mono's ``mcs`` and run with ``mono``.

``clients/unity/`` is a Unity package; its Mono-testable core (``Runtime/`` but
``Runtime/Unity/``) and the console grid engine (``Samples~/GridEngine/``) compile here
against Debian's Newtonsoft.Json (``make test`` installs ``mono-devel`` and
``libnewtonsoft-json-cil-dev``). Builds go to ``clients/unity/.build/`` and are redone
when a source is newer than its output.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from bridge.errors import BridgeError
from bridge.processes import CHECKOUT

SDK = "clients/unity"
BUILD = CHECKOUT / SDK / ".build"
NEWTONSOFT_PKG = "newtonsoft-json"
INSTALL_HINT = "apt-get install mono-devel libnewtonsoft-json-cil-dev (make test does it)"


def _newtonsoft() -> list[str]:
    """The ``-r:`` reference to Debian's Newtonsoft.Json."""
    try:
        flags = subprocess.run(
            ["pkg-config", "--libs", NEWTONSOFT_PKG], capture_output=True, text=True, check=True
        ).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        raise BridgeError(f"Newtonsoft.Json for Mono is not installed: {INSTALL_HINT}") from None
    return flags


def sdk_sources() -> list[Path]:
    """The SDK's Mono-testable C# files (``Runtime/`` without the Unity adapter)."""
    runtime = CHECKOUT / SDK / "Runtime"
    return sorted(p for p in runtime.rglob("*.cs") if "Unity" not in p.relative_to(runtime).parts)


def _stale(output: Path, sources: list[Path]) -> bool:
    return not output.exists() or any(s.stat().st_mtime > output.stat().st_mtime for s in sources)


def _mcs(output: Path, sources: list[Path], *extra: str) -> None:
    if shutil.which("mcs") is None:
        raise BridgeError(f"Mono's C# compiler (mcs) is not installed: {INSTALL_HINT}")
    output.parent.mkdir(parents=True, exist_ok=True)
    target = ["-target:library"] if output.suffix == ".dll" else []
    command = ["mcs", "-nologo", "-warnaserror+", *target, f"-out:{output}", *_newtonsoft(), *extra]
    result = subprocess.run([*command, *map(str, sources)], capture_output=True, text=True)
    if result.returncode != 0:
        raise BridgeError(f"mcs could not build {output.name}:\n{result.stdout}{result.stderr}")


def build(build_dir: Path = BUILD) -> dict[str, Path]:
    """Compile what is stale: ``Toyroom.dll`` (the SDK), ``GridEngine.exe`` (the sample) and
    ``RoundTrip.exe`` (the message classes' self-test); their paths by name.

    Raises:
        BridgeError: Mono is not installed, or a file does not compile (with mcs's messages).
    """
    if not (CHECKOUT / SDK).is_dir():
        raise BridgeError(f"the C# SDK needs a source checkout ({SDK} is not in the installed package)")
    sdk = build_dir / "Toyroom.dll"
    sources = sdk_sources()
    if _stale(sdk, sources):
        _mcs(sdk, sources)
    outputs = {"Toyroom.dll": sdk}
    programs = {
        "GridEngine.exe": CHECKOUT / SDK / "Samples~" / "GridEngine",
        "RoundTrip.exe": CHECKOUT / SDK / "Tests" / "Mono",
    }
    for name, folder in programs.items():
        exe = build_dir / name
        files = sorted(folder.glob("*.cs"))
        if _stale(exe, [*files, sdk]):
            _mcs(exe, files, f"-r:{sdk}", "-r:System.Core.dll")
        outputs[name] = exe
    return outputs


def export_scenario(name: str, folder: Path) -> Path:
    """``python -m sim2d export`` of scenario ``name`` (a bundled name or a ``.toml`` path)
    into ``folder/<stem>.json``, which the C# engine reads."""
    stem = Path(name).stem if name.endswith(".toml") else name
    out = folder / f"{stem}.json"
    result = subprocess.run(
        [sys.executable, "-m", "sim2d", "export", "--scenario", name, "--out", str(out)],
        capture_output=True,
        text=True,
    )
    if result.returncode != 0:
        raise BridgeError(f"cannot export scenario '{name}': {result.stderr.strip()}")
    return out


def engine_command(gateway: str, scenarios: Path, *args: str) -> list[str]:
    """The C# grid engine's command line, on the gateway at ``gateway`` with the exports in
    ``scenarios`` (``args``: ``--scenario``, ``--robot``...)."""
    exe = build()["GridEngine.exe"]
    return ["mono", "--debug", str(exe), "--gateway", gateway, "--scenarios", str(scenarios), *args]

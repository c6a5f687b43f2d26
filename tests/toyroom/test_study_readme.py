"""The README's study, run as a study team would: its commands copied from the README's
"Running a small study with people" block (only the counts of participants and raters made
small: 3 and 2), each run by bash in a fresh folder. Three participants in headless Chromium
(two play ``paper-robot`` to its goal, one presses Start, takes a step and goes no further),
the play server stopped with Ctrl-C once the two are done (the third's world cut short);
``toyroom infer`` on a recording; two raters answering every question at once, each in a
browser of their own; ``toyroom fit`` on what they wrote. Every command exits 0; ``rate``
and ``fit`` leave out the incomplete recording and say so, and the fit's report names the
ratings and the raters (issue 55)."""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from tests.toyroom.devtools import Browser, Tab
from tests.toyroom.output import OutputLines
from tests.toyroom.play.participant import play_paper_robot_to_the_goal, press_start

pytestmark = [
    pytest.mark.sweep,  # minutes of play and rating in real time: `make sweeps` (tests/tiers.py)
    pytest.mark.skipif(shutil.which("chromium") is None, reason="chromium is not installed"),
]
README = Path(__file__).parents[2] / "README.md"
SMALL = {"--participants 10": "--participants 3", "--participants 20": "--participants 2"}


def readme_commands() -> list[str]:
    """The study block's commands, as the README writes them (counts made small)."""
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Running a small study with people") :]
    block = section[section.index("```sh") + len("```sh") : section.index("```", section.index("```sh") + 5)]
    commands = [line.split("   #")[0].strip() for line in block.splitlines() if line.startswith("toyroom ")]
    for big, small in SMALL.items():
        assert sum(big in c for c in commands) == 1, f"the README's study no longer says {big!r}: {commands}"
        commands = [c.replace(big, small) for c in commands]
    return commands


class Shell:
    """One README command run by bash in the study's folder, its output lines collected."""

    def __init__(self, line: str, folder: Path) -> None:
        env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
        self.line = line
        self.process = subprocess.Popen(
            ["bash", "-c", line], cwd=folder, env=env, text=True, start_new_session=True,
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        )  # fmt: skip
        self.output = OutputLines(self.process, line)

    @property
    def lines(self) -> list[str]:
        return self.output.lines

    def wait_line(self, pattern: str, timeout: float) -> str:
        return self.output.wait(pattern, timeout)

    def interrupt(self) -> None:
        """Ctrl-C, as the README says once everyone is done."""
        os.killpg(self.process.pid, signal.SIGINT)

    def finish(self, timeout: float) -> str:
        code = self.process.wait(timeout=timeout)
        output = "\n".join(self.lines)
        assert code == 0, f"`{self.line}` exited {code}:\n{output[-3000:]}"
        return output


def _rate_everything(tab: Tab, link: str) -> int:
    """A rater: consent, then every question (each replay watched to its end, every slider
    moved); how many questions they answered."""
    tab.goto(link)
    tab.evaluate("document.getElementById('agree').click(); 0")
    answered = 0
    while not tab.evaluate("!document.getElementById('done').hidden"):
        tab.evaluate("window.replayDone")
        tab.evaluate(
            "document.querySelectorAll('#sliders input').forEach((s, n) => {"
            " s.value = 20 + 30 * n; s.dispatchEvent(new Event('input')); }); 0"
        )
        tab.events.clear()
        tab.evaluate("document.getElementById('submit').click(); 0")
        tab.wait_event("Page.loadEventFired", 60)
        answered += 1
        assert answered < 50, "the rater never reached the end"
    return answered


def test_the_readmes_study_runs_end_to_end(tmp_path: Path) -> None:
    play, infer, rate, fit = readme_commands()
    (tmp_path / "examples").symlink_to(README.parent / "examples")  # the README runs in the checkout
    assert play.startswith("toyroom play") and infer.startswith("toyroom infer"), (play, infer)
    served = Shell(play, tmp_path)
    try:
        links = [served.wait_line(rf"participant p{n}: http", 120).split(": ", 2)[-1] for n in (1, 2, 3)]
        with Browser() as browser:
            p3 = browser.open(links[2])
            press_start(p3)
            p3.press("ArrowRight")  # the third participant takes a step and goes no further
            for link in links[:2]:
                tab = browser.open(link)
                ended = play_paper_robot_to_the_goal(tab)
                assert ended == "goal reached", f"{link}: the world ended {ended!r}"
                browser.close_tab(tab)
            for name in ("p1", "p2"):
                served.wait_line(rf"participant {name}: recording .* \(complete, goal_reached", 180)
            served.interrupt()  # the README: Ctrl-C when all are done; p3's world is cut short
            output = served.finish(180)
    finally:
        if served.process.poll() is None:
            served.process.kill()
    assert re.search(r"participant p3: recording .* \(incomplete", output), output[-2000:]
    print("\n".join(line for line in output.splitlines() if "recording" in line or "goal" in line))

    assert "mind.csv" in Shell(infer, tmp_path).finish(600)

    rating = Shell(rate, tmp_path)
    try:
        rating.wait_line(r"toyroom rate: ready", 120)
        out = "\n".join(rating.lines)
        print(out)
        assert "left out an incomplete play recording: out/study/p3.mcap" in out, out
        rater_links = [rating.wait_line(rf"^  p{n}: http", 10).split(": ", 1)[-1] for n in (1, 2)]
        counts: list[int] = []

        def rater(link: str) -> None:
            with Browser() as own:  # a browser each: a background tab's timers are throttled
                counts.append(_rate_everything(own.first_tab(), link))

        threads = [threading.Thread(target=rater, args=(link,)) for link in rater_links]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=900)
        assert len(counts) == 2 and counts[0] == counts[1] == 8, f"questions answered by each rater: {counts}"
        rating.interrupt()
        rating.finish(60)
    finally:
        if rating.process.poll() is None:
            rating.process.kill()

    fitted = Shell(fit, tmp_path).finish(900)
    print("\n".join(line for line in fitted.splitlines() if line.startswith("toyroom fit")))
    assert "excluded an incomplete play recording: out/study/p3.mcap" in fitted, fitted[-3000:]
    report = (tmp_path / "out" / "fit" / "report.md").read_text(encoding="utf-8")
    assert re.search(r"\d+ ratings by 2 raters, of 2 recording\(s\)", report), report
    print(report)
    assert "## Written" in report and (tmp_path / "out" / "fit" / "settings.toml").is_file(), report

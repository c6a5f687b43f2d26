"""The rating page, one HTML document per request: the study's texts, the participant's
next question with its replay data inlined (``window.RATING``), and :mod:`.script`. Laid out
for 1000 x 750: the map on the left, the question and its sliders on the right."""

from __future__ import annotations

import html
import json
from typing import Any

from .questions import Question, RatingStudy
from .script import SCRIPT

STYLE = """
body { font-family: sans-serif; margin: 0; color: #222; background: #f4f4f4; }
header { display: flex; justify-content: space-between; padding: 8px 16px; background: #2b3a4a;
  color: #fff; font-size: 18px; }
main { padding: 10px 16px; }
#task { display: flex; gap: 16px; }
canvas { background: #fff; border: 1px solid #bbb; }
#side { width: 300px; }
#side h2 { font-size: 20px; margin: 4px 0 10px; }
.slider { display: grid; grid-template-columns: 125px 1fr 30px; align-items: center; gap: 6px;
  margin: 8px 0; font-size: 15px; }
button { font-size: 16px; padding: 6px 16px; margin: 8px 8px 0 0; }
.text { white-space: pre-wrap; background: #fff; padding: 12px; border: 1px solid #ccc; max-width: 760px; }
#tick, #status, #agreeStatus { color: #666; font-size: 14px; }
#said { font-size: 15px; margin: 6px 0; min-height: 3.6em; }
#said div { margin: 2px 0; }
"""

BODY = """
<header><span>{title}</span><span>{progress}</span></header>
<main>
<section id="consent" hidden>
  <h2>Instructions</h2><div class="text">{instructions}</div>
  <h2>Consent</h2><div class="text">{consent}</div>
  <button id="agree">I agree, start</button><div id="agreeStatus"></div>
</section>
<section id="task" hidden>
  <canvas id="map" width="640" height="600"></canvas>
  <div id="side">
    <h2 id="prompt"></h2>
    <div id="tick"></div>
    <div id="said"></div>
    <div id="sliders"></div>
    <button id="again">Watch again</button><button id="submit" disabled>Next</button>
    <div id="status"></div>
  </div>
</section>
<section id="done" hidden><h2>All questions answered. Thank you!</h2>
  <p>You may close this page.</p></section>
</main>
"""


def page_state(
    question: Question | None,
    *,
    answered: int,
    answer_url: str,
    consent_url: str = "",
    consented: bool = False,
    plan: dict[str, Any] | None,
    frames: list[dict[str, Any]],
    captions: list[dict[str, Any]] | None = None,
    rate: float = 2.0,
    tick_seconds: float = 0.1,
) -> dict[str, Any]:
    """``window.RATING``: the question (``None`` when all are answered; its text is shown only
    after consent), how many the participant has answered, where to send the answer and the
    consent, whether the server has the participant's consent (the page then skips it), and the
    replay: plan, frames, captions (what was said, by tick), its rate (times real time) and the
    recording's tick (s)."""
    asked = None
    if question is not None:
        asked = {
            "id": question.id,
            "person": question.person,
            "targets": list(question.targets),
            "labels": list(question.labels),
            "text": question.text,
        }
    return {
        "question": asked,
        "answered": answered,
        "answerUrl": answer_url,
        "consentUrl": consent_url,
        "consented": consented,
        "plan": plan,
        "frames": frames,
        "captions": captions or [],
        "rate": rate,
        "tickSeconds": tick_seconds,
    }


def render(study: RatingStudy, participant: str, question: Question | None, state: dict[str, Any]) -> str:
    """The page for ``participant`` at ``question`` (``None``: the thank-you page)."""
    total = len(study.questions)
    number = min(state["answered"] + 1, total)
    progress = f"{participant}: question {number} of {total}" if question else f"{participant}: done"
    data = json.dumps(state, separators=(",", ":")).replace("</", "<\\/")
    body = BODY.format(
        title=html.escape(study.title),
        progress=html.escape(progress),
        instructions=html.escape(study.instructions),
        consent=html.escape(study.consent),
    )
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{html.escape(study.title)}</title><style>{STYLE}</style></head><body>{body}"
        f"<script>window.RATING = {data};</script><script>{SCRIPT}</script></body></html>\n"
    )

"""``toyroom rate``: a judgments page in the manner of Baker et al. Participants watch a
recording up to each question's tick (drawn from above on a canvas) and rate, on sliders,
where a person thinks an item is or how much they want each item; the answers go to a CSV
that ``toyroom fit --judgments`` reads. The questions file (:mod:`.questions`), what the
page draws (:mod:`.drawing`), the answers file (:mod:`.answers`), the page (:mod:`.page`,
:mod:`.script`), each participant's consent and place (:mod:`.progress`), the server
(:mod:`.server`) and the command (:mod:`.node`)."""

from .answers import COLUMNS, AnswerBook
from .questions import Question, QuestionsError, RatingStudy, load_study
from .server import RatingServer, RatingSettings, token_for

__all__ = [
    "load_study",
    "token_for",
    "AnswerBook",
    "COLUMNS",
    "Question",
    "QuestionsError",
    "RatingServer",
    "RatingSettings",
    "RatingStudy",
]

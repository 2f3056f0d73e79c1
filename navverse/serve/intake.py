"""An upload checked against its split before it is accepted: any problem refuses it.

:func:`check_upload` reads the stored body with the evaluator's own reader
(:func:`navverse.eval.submission.read_submission`, within its :class:`~navverse.eval.submission.Limits`:
decompressed size, lines, rows), against the split's public episode ids and its scenes' bounds, and
asks what the scorer would (one track, one PlaceNav instruction type). Where ``navverse eval`` would
score the valid records and count the others as failures, the server refuses the whole submission with
the first problems, so that a team does not spend a day's submission on a typo. Messages name the
submission, never the server's file.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from navverse.serve.benchmark import SplitInfo
from navverse.serve.errors import RefusedError

__all__ = ["Checked", "check_upload"]

_NOT_COUNTED = "nothing was counted against your team's daily submissions"


@dataclass(frozen=True)
class Checked:
    """What an accepted upload holds.

    Attributes
    ----------
    lines : int
        Lines read.
    records : int
        Valid records (one per episode submitted).
    track : dict
        Its agent's sensors and privileges (:func:`navverse.eval.scoring.submission_track`).
    instruction_type : str or None
        The PlaceNav instruction type it was run under; None when the split has no PlaceNav episode.
    """

    lines: int
    records: int
    track: dict
    instruction_type: str | None


def _public(message: str, path: Path) -> str:
    """A reader's message about the stored file, naming "the submission" instead of the file."""
    return message.replace(str(path), "the submission")


def check_upload(path: Path, split: SplitInfo, *, shown: int = 20) -> Checked:
    """Check a stored upload against `split`; returns what it holds.

    Parameters
    ----------
    path : Path
        The upload (JSONL, or gzip by its magic bytes).
    split : SplitInfo
        The split it is submitted to (scoreable: its bounds are known).
    shown : int
        Problems listed in a refusal (the others are counted).

    Raises
    ------
    RefusedError
        422: the file cannot be read (damaged gzip, not UTF-8, over a cap of the reader: a gzip bomb
        is refused once its text passes the cap, before any line is parsed), a line has a problem
        (malformed JSON, an unknown or duplicate episode id, a bad row...: the first `shown` problems
        with their line numbers), no record at all, a submission to a private split without a line
        for each of its episodes, or records that disagree on their track or instruction type.
    """
    from navverse.eval.scoring import instruction_type_of, submission_track
    from navverse.eval.submission import SubmissionError, read_submission

    try:
        submission = read_submission(path, episode_ids=split.episode_ids, bounds=split.bounds)
    except SubmissionError as exc:
        raise RefusedError(422, f"{_public(str(exc), path)} ({_NOT_COUNTED})") from None
    problems = submission.problems
    if problems:
        count = len(problems) + submission.omitted
        listed = "; ".join(str(p) for p in problems[:shown])
        more = f"; ... and {count - shown} more" if count > shown else ""
        raise RefusedError(
            422,
            f"the submission has {count} problem{'s' if count != 1 else ''}, so it was not accepted "
            f"({_NOT_COUNTED}): {listed}{more}. Fix them and send it again (`navverse validate submission` "
            f"with this dataset and --split {split.name} lists every problem)",
        )
    if not submission.records:
        raise RefusedError(
            422,
            f"the submission has no record: it is JSON lines, one object per episode of split "
            f"{split.name!r} ({_NOT_COUNTED})",
        )
    missing = sorted(split.episode_ids - set(submission.records)) if split.private else []
    if missing:
        raise RefusedError(
            422,
            f"a submission to the private split {split.name!r} has a line for each of its "
            f"{len(split.episode_ids)} episodes (so that no score is a mean over a few hidden goals); "
            f"{len(missing)} are missing, the first: {', '.join(missing[:5])} ({_NOT_COUNTED})",
        )
    try:
        track = submission_track(submission)
        kind = instruction_type_of(submission, split.episodes)
    except SubmissionError as exc:
        raise RefusedError(422, f"{_public(str(exc), path)} ({_NOT_COUNTED})") from None
    return Checked(
        lines=submission.lines, records=len(submission.records), track=track, instruction_type=kind
    )

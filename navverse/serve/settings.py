"""The settings of the evaluation server, one declaration each (:class:`ServeSettings`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator

from navverse.settings import Settings

__all__ = ["MIB", "ServeSettings"]

MIB = 2**20


class ServeSettings(Settings):
    """How the server scores, renews its claims and bounds what it takes.

    The lease of a claimed submission is short and renewed every ``heartbeat_seconds`` while it is
    scored, so that a server killed mid-scoring has its work taken up by the next server to look
    (itself restarted, or another on the same database) once ``lease_seconds`` have passed.
    """

    workers: Annotated[int, Field(ge=1, le=64)] = 1
    """Scoring processes (each scores one submission at a time)."""
    rate_per_day: Annotated[int, Field(ge=1, le=100_000)] = 5
    """Submissions a team may have accepted in any 24 hours."""
    max_body_bytes: Annotated[int, Field(ge=1024, le=4096 * MIB)] = 64 * MIB
    """Largest request body (a submission file as sent, gzip or not)."""
    lease_seconds: Annotated[float, Field(gt=0.5, le=3600.0)] = 20.0
    """How long a claim holds without a heartbeat; after it any server may take the submission over."""
    heartbeat_seconds: Annotated[float, Field(gt=0.05, le=600.0)] = 5.0
    """How often a scoring server renews the leases of the submissions it scores."""
    poll_seconds: Annotated[float, Field(gt=0.05, le=600.0)] = 1.0
    """How often an idle server looks for queued work (a submission it accepted wakes it at once)."""
    max_attempts: Annotated[int, Field(ge=1, le=100)] = 3
    """Claims of one submission before it is marked failed (a scoring that keeps killing its worker)."""
    validations: Annotated[int, Field(ge=1, le=64)] = 1
    """Uploads checked at once (each holds its valid trajectories in memory while checked)."""
    problems_shown: Annotated[int, Field(ge=1, le=1000)] = 20
    """Problems of a refused submission listed in its 422 (the others are counted)."""
    max_connections: Annotated[int, Field(ge=4, le=100_000)] = 64
    """Connections served at once; more are answered 503."""

    @model_validator(mode="after")
    def _heartbeat_within_lease(self) -> ServeSettings:
        if self.heartbeat_seconds * 2 > self.lease_seconds:
            raise ValueError(
                f"heartbeat_seconds ({self.heartbeat_seconds:g}) must be at most half of lease_seconds "
                f"({self.lease_seconds:g}), so that a claim is renewed well before it runs out"
            )
        return self

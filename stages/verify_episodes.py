"""The verify_episodes stage: every candidate run under full physics; those that pass, and why others fail."""

from __future__ import annotations

from navverse.episodes.verification import VerificationSettings
from pipeline import Input, Params, StageContext, stage


class VerifyEpisodesParams(Params, VerificationSettings):
    """Parameters of :func:`verify_episodes` (Appendix D.2; the robot is the candidates' own): those of
    :class:`navverse.episodes.verification.VerificationSettings`, the acceptance bounds of a rollout
    (``duration_s``, ``traveled_m``) and the objects given collision geometry (``object_margin_m``)."""


@stage(
    name="verify_episodes",
    inputs=["candidates", Input("scene", many=True)],
    outputs=["verified"],
    summary={"candidates": "candidates", "accepted": "accepted_by_task", "rejected": "rejected_by_reason"},
)
def verify_episodes(ctx: StageContext, params: VerifyEpisodesParams) -> None:
    """episodes.json.gz (accepted, with their verification), rollouts, and rejections with reasons."""
    from collections import Counter

    from navverse.episodes import files
    from navverse.episodes.verification import verify_episodes as run
    from navverse.records.jsongz import read_json_gz, write_json_gz
    from navverse.records.schema import Episode
    from navverse.scene.directory import read_annotations

    candidates = read_json_gz(ctx.input("candidates") / files.CANDIDATES)
    episodes = [Episode.model_validate(e) for e in candidates["episodes"]]
    scene_dirs = {read_annotations(path).scene_id: path for path in ctx.inputs["scene"]}
    missing = sorted({e.scene_id for e in episodes} - set(scene_dirs))
    if missing:
        raise RuntimeError(f"candidates of scenes that are not linked: {', '.join(missing)}")
    ctx.progress(0, len(scene_dirs), "verifying")
    results = run(
        episodes,
        scene_dirs,
        embodiment=candidates["embodiment"],
        settings=VerificationSettings.of(params),
        mapper=lambda fn, tasks: ctx.map(fn, tasks, chunksize=1),  # a scene per job, on the build's executor
    )
    accepted, rollouts, rejections = [], {}, []
    for episode, result in zip(episodes, results, strict=True):
        if result.accepted:
            info = episode.info.model_copy(update={"verification": result.verification})
            accepted.append(episode.model_copy(update={"info": info}).model_dump(mode="json"))
            rollouts[episode.episode_id] = [[round(float(v), 4) for v in row] for row in result.trajectory]
        else:
            rejections.append(
                {
                    "episode_id": episode.episode_id,
                    "scene_id": episode.scene_id,
                    "task": episode.task,
                    "reason": result.reason,
                    "duration_s": result.verification.duration_s,
                    "traveled_m": result.verification.traveled_m,
                }
            )
    write_json_gz({"embodiment": candidates["embodiment"], "episodes": accepted}, ctx.output / files.EPISODES)
    write_json_gz(rollouts, ctx.output / files.ROLLOUTS)
    write_json_gz(rejections, ctx.output / files.REJECTIONS)
    reasons = Counter(r["reason"] for r in rejections)
    by_task = Counter(e["task"] for e in accepted)
    rate = len(accepted) / len(episodes) if episodes else 0.0
    ctx.record(
        candidates=len(episodes),
        accepted=len(accepted),
        acceptance_rate=round(rate, 4),
        accepted_by_task=dict(sorted(by_task.items())),
        rejected_by_reason=dict(sorted(reasons.items())),
    )
    ctx.log.info(
        "accepted %d of %d candidates (%.1f%%); rejected: %s", len(accepted), len(episodes), 100 * rate,
        ", ".join(f"{k} {v}" for k, v in sorted(reasons.items())) or "none",
    )  # fmt: skip

"""How each v1 difficulty level (and each of its parts alone) hurts the scripted pilots.

For each v1 env: its tuned pilot (tuned on v0: a pilot that never saw the level) and random
actions fly the first episode of ``--episodes`` sub-envs reset with the evaluation seed
(``fluidsim_envs.evaluation.EVAL_SEED``), the same episodes for every row, at ``easy``,
``standard`` and ``hard``, and at ``easy`` with one part of ``standard`` switched on at a
time (the randomized physics, the instruments, the actuators, the moving air or water): what
each part costs the pilot. Success rates with their 95% Wilson intervals, mean returns with
their bootstrap intervals (``rl.evaluate.summarize``).

Writes ``docs/study_levels.csv``; :func:`markdown` renders it for docs/environments.md
(``benchmarks.report``).

    python -m benchmarks.study_levels [--quick] [--episodes N]
"""

from __future__ import annotations

import importlib
import time

import gymnasium as gym

import fluidsim_envs  # noqa: F401  (registers the ids)
from benchmarks.common import DOCS, arguments, describe, read_csv, wilson, write_csv
from fluidsim_envs.evaluation import EVAL_SEED, first_episodes, random_policy
from fluidsim_envs.rl.evaluate import summarize
from fluidsim_envs.scenes import SCENES

# the parts of a level, each the knobs that switch it on (the rest of easy kept)
PARTS = {
    "physics": ("mass_scale", "inertia_scale", "com_shift_m", "area_scale", "efficiency_scale",
                "thrust_scale", "density_scale"),
    "sensors": ("sensor_scale", "sensor_latency_steps"),
    "actuators": ("actuators", "surface_time_constant_s", "surface_rate_dps",
                  "thrust_time_constant_s", "thrust_rate_per_s"),
    "moving air or water": ("turbulence", "gust_mps", "gust_duration_s", "gust_within_s",
                            "current_mps", "current_variation_mps", "current_time_s",
                            "wind_mps", "sea_hs_m", "sea_tp_s", "sea_gamma"),
}  # fmt: skip
COLUMNS = ("env", "setting", "policy", "episodes", "success_rate", "success_low",
           "success_high", "return_mean", "return_low", "return_high", "diverged")  # fmt: skip


def settings(env_id: str) -> list[tuple[str, dict]]:
    """(label, make kwargs) of the rows for ``env_id``: each level, then each part of
    standard alone on easy (parts the scene does not have are left out)."""
    module = importlib.import_module(SCENES[env_id].vector_cls.__module__)
    standard = module.LEVELS["standard"]
    rows = [(level, {"difficulty": level}) for level in ("easy", "standard", "hard")]
    for part, knobs in PARTS.items():
        own = {k: v for k, v in standard.items() if k in knobs}
        if own:
            rows.append((f"easy + standard's {part}", {"difficulty": "easy", **own}))
    return rows


def fly(env_id: str, kwargs: dict, episodes: int) -> list[dict]:
    venv = gym.make_vec(env_id, num_envs=episodes, vectorization_mode="vector_entry_point",
                        **kwargs)  # fmt: skip
    env = venv.unwrapped
    rows = []
    for name, policy in (("tuned pilot", SCENES[env_id].pilot(env)),
                         ("random", random_policy(env, EVAL_SEED))):  # fmt: skip
        out = first_episodes(env, policy, seed=EVAL_SEED)
        row = summarize(name, out, EVAL_SEED)
        k = int(out["success"].sum())
        lo, hi = wilson(k, episodes)
        rows.append({
            "policy": name, "episodes": episodes, "success_rate": k / episodes,
            "success_low": lo, "success_high": hi, "return_mean": row["return_mean"],
            "return_low": row["return_mean_lo"], "return_high": row["return_mean_hi"],
            "diverged": int(out["physics_diverged"].sum()),
        })  # fmt: skip
    venv.close()
    return rows


def main() -> None:
    parser = arguments(__doc__, "16 episodes, into build/", "study_levels.csv")
    parser.add_argument("--episodes", type=int, default=None, help="episodes per row")
    args = parser.parse_args()
    episodes = args.episodes or (16 if args.quick else 256)
    out = args.out if not args.quick else DOCS.parent / "build" / "study_levels_quick.csv"
    rows, t0 = [], time.perf_counter()
    for env_id in (i for i, s in SCENES.items() if s.version == 1):
        for label, kwargs in settings(env_id):
            for r in fly(env_id, kwargs, episodes):
                rows.append({"env": env_id.split("/")[1], "setting": label, **r})
            print(f"{env_id} {label}: {time.perf_counter() - t0:.0f} s", flush=True)
    cells = [[f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]) for c in COLUMNS]
             for r in rows]  # fmt: skip
    out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(out, COLUMNS, cells, describe())
    print(f"wrote {out}\n{markdown(out)}")


def markdown(path=None) -> str:
    """docs/environments.md's table of the pilots per level from ``docs/study_levels.csv``."""
    path = DOCS / "study_levels.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_levels.csv yet: run python -m benchmarks.study_levels)"
    _, rows = read_csv(path)
    lines = [
        "| env | setting | tuned pilot: success [95%] | return [95%] | random: success "
        "| diverged (pilot) |",
        "|---|---|---:|---:|---:|---:|",
    ]
    by = {(r["env"], r["setting"], r["policy"]): r for r in rows}
    for (env, setting, policy), r in by.items():
        if policy != "tuned pilot":
            continue
        rnd = by.get((env, setting, "random"))
        pct = lambda x: f"{100 * float(x):.0f}%"  # noqa: E731
        lines.append(
            f"| {env} | {setting} | {pct(r['success_rate'])} [{pct(r['success_low'])}, "
            f"{pct(r['success_high'])}] | {float(r['return_mean']):.1f} "
            f"[{float(r['return_low']):.1f}, {float(r['return_high']):.1f}] | "
            f"{pct(rnd['success_rate']) if rnd else ''} | {r['diverged']} |"
        )
    n = rows[0]["episodes"] if rows else "?"
    lines += ["", f"{n} episodes per row, the same seeded episodes in every row of an env."]
    return "\n".join(lines)


if __name__ == "__main__":
    main()

"""What each reward term gives the tuned pilot per episode, at each level of a v1 env.

A return says little about what pays for it: this flies the scene's tuned pilot (tuned on v0)
on ``--episodes`` seeded episodes at each level and reports the per-episode mean of each of
``info["episode_terms"]`` (the first episode of each sub-env), so a term that swamps the
others at some level shows at once. Where the scene's pilot holds a target speed (its
observation has ``speed_error`` and ``target_speed``: the boat), the same pilot also flies
holding each of :data:`HOLD_SPEEDS` instead of the episode's target, under the shipped
reward and under what it replaced (:data:`REWARDS`): whether a reward pays more for crawling
the course than for running it (v0's porpoising term did in moving water, issue 23).

Writes ``docs/reward_terms.csv`` (a row per env, level, reward, policy and term; ``--quick``: into
build/); :func:`markdown` renders the boat's for docs/environments.md
(``benchmarks.report``).

    python -m benchmarks.reward_terms [--env fluidsim/BoatOnStep-v1] [--episodes 64]
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import fluidsim_envs  # noqa: F401  (registers the ids)
from benchmarks.common import DOCS, ROOT, arguments, describe, read_csv, wilson, write_csv
from fluidsim_envs.evaluation import EVAL_SEED
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.realism import LEVELS

CSV = DOCS / "reward_terms.csv"
COLUMNS = ("env", "level", "reward", "policy", "episodes", "success_rate", "success_low",
           "success_high", "return_mean", "term", "term_mean")  # fmt: skip
HOLD_SPEEDS = (12.0, 9.0)  # m/s: below the boat's targets (13-19), and below planing (10)
# each env's reward as shipped ("v1"), and what it replaced, as make kwargs
REWARDS = {
    "BoatOnStep-v1": {"v1": {}, "v0's porpoising term": {"w_porpoise": 0.05, "w_ride": 0.0}},
}


def held(pilot, names: list[str], speed: float):
    """``pilot`` flying as if each episode's target speed were ``speed`` (m/s)."""
    error, target = names.index("speed_error"), names.index("target_speed")

    def policy(obs):
        obs = obs.copy()
        obs[:, error] -= obs[:, target] - speed
        obs[:, target] = speed
        return pilot(obs)

    policy.reset = pilot.reset
    return policy


def policies(env_id: str, env) -> dict:
    """The tuned pilot, and where it holds a speed, the same pilot at each held speed: each
    a pilot of its own (a pilot keeps state between steps)."""
    scene = SCENES[env_id]
    out = {"tuned pilot": scene.pilot(env)}
    names = [name for name, _, _ in scene.observation]
    if "speed_error" in names and "target_speed" in names:
        for speed in HOLD_SPEEDS:
            out[f"tuned pilot at {speed:g} m/s"] = held(scene.pilot(env), names, speed)
    return out


def fly(venv, policy, seed: int) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Each reward term's sum and success over the first episode of every sub-env."""
    n = venv.num_envs
    obs, _ = venv.reset(seed=seed)
    getattr(policy, "reset", lambda: None)()
    done = np.zeros(n, dtype=bool)
    sums = {name: np.zeros(n) for name in venv.unwrapped.reward_terms}
    success = np.zeros(n, dtype=bool)
    while not done.all():
        obs, _, _, _, info = venv.step(policy(obs))
        if "episode_terms" in info:
            first = info["_episode_terms"] & ~done
            for name, values in info["episode_terms"].items():
                sums[name][first] = values[first]
            success[first] = info["success"][first]
            done |= first
    return sums, success


def rows(env_id: str, level: str, episodes: int, seed: int) -> list[dict]:
    out = []
    for reward, kwargs in REWARDS.get(env_id.split("/")[1], {"v1": {}}).items():
        venv = gym.make_vec(env_id, num_envs=episodes, vectorization_mode="vector_entry_point",
                            difficulty=level, **kwargs)  # fmt: skip
        for name, policy in policies(env_id, venv.unwrapped).items():
            sums, success = fly(venv, policy, seed)
            lo, hi = wilson(int(success.sum()), episodes)
            ret = sum(sums.values()).mean()
            for term, values in sums.items():
                out.append({
                    "env": env_id.split("/")[1], "level": level, "reward": reward,
                    "policy": name, "episodes": episodes, "success_rate": success.mean(),
                    "success_low": lo, "success_high": hi, "return_mean": ret, "term": term,
                    "term_mean": values.mean(),
                })  # fmt: skip
            terms = "  ".join(f"{k} {v.mean():7.1f}" for k, v in sums.items())
            print(f"{env_id} {level:9s} {reward:21s} {name:24s} success {success.mean():.2f} "
                  f"return {ret:7.1f}  {terms}", flush=True)  # fmt: skip
        venv.close()
    return out


def main(argv: list[str] | None = None) -> int:
    parser = arguments(__doc__, "16 episodes", "reward_terms.csv")
    v1 = [i for i, s in SCENES.items() if s.version == 1]
    parser.add_argument("--env", action="append", choices=v1, help="(default: every v1 env)")
    parser.add_argument("--episodes", type=int, default=64)
    args = parser.parse_args(argv)
    episodes = 16 if args.quick else args.episodes
    if args.quick and args.out == parser.get_default("out"):
        args.out = ROOT / "build" / "reward_terms.csv"  # a quick run never replaces the docs'
        args.out.parent.mkdir(exist_ok=True)
    if episodes < 1:
        parser.error(f"--episodes must be at least 1, got {episodes}")
    out = []
    for env_id in args.env or v1:
        for level in LEVELS:
            out += rows(env_id, level, episodes, EVAL_SEED)
    write_csv(args.out, COLUMNS, ([r[c] for c in COLUMNS] for r in out), describe())
    print(f"wrote {args.out}")
    return 0


def markdown(path=None, env: str = "BoatOnStep-v1") -> str:
    """docs/environments.md's table of ``env``'s reward terms per level and policy."""
    path = CSV if path is None else path
    if not path.is_file():
        return "(no docs/reward_terms.csv yet: run python -m benchmarks.reward_terms)"
    _, table = read_csv(path)
    table = [r for r in table if r["env"] == env]
    terms = list(dict.fromkeys(r["term"] for r in table))
    runs = list(dict.fromkeys((r["level"], r["reward"], r["policy"]) for r in table))
    by = {(r["level"], r["reward"], r["policy"], r["term"]): r for r in table}
    pct = lambda x: f"{100 * float(x):.0f}%"  # noqa: E731
    lines = ["| level | reward | policy | success [95%] | return | " + " | ".join(terms) + " |",
             "|---|---|---|---:|---:|" + "---:|" * len(terms)]  # fmt: skip
    for run in runs:
        r = by[(*run, terms[0])]
        cells = " | ".join(f"{float(by[(*run, t)]['term_mean']):.1f}" for t in terms)
        lines.append(
            f"| {' | '.join(run)} | {pct(r['success_rate'])} [{pct(r['success_low'])}, "
            f"{pct(r['success_high'])}] | {float(r['return_mean']):.1f} | {cells} |"
        )
    n = table[0]["episodes"] if table else "?"
    lines += ["", f"Per-episode means over {n} seeded episodes per row (the evaluation seed), "
              "the same episodes in every row of a level."]  # fmt: skip
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())

"""Time one peer simulator in this process and print one ``RESULT {json}`` line.

Run by ``benchmarks/bench_peers.py`` with the python of ``benchmarks/.peers-venv`` (the peers
need packages that must not enter the project's environment: PyFlyt 0.29.0 wants numpy < 2 and
pybullet). It imports nothing from the project, so that it runs in that venv as it is.

    benchmarks/.peers-venv/bin/python benchmarks/peers_child.py pyflyt 1.0 3
    benchmarks/.peers-venv/bin/python benchmarks/peers_child.py jsbsim 1.0 3

Arguments: the peer (``pyflyt`` or ``jsbsim``), the seconds of one timed run, the number of
runs (the best is kept). Measured:

- ``pyflyt``: ``PyFlyt/Fixedwing-Waypoints-v3`` (the fixed-wing id PyFlyt 0.29.0 registers),
  one env (``gym.make``), stepped with random actions drawn beforehand; an episode end resets
  inside the timed loop, as in training. Reported: env-steps/s including those resets, the
  seconds the resets took (so that the rate of the steps alone follows), and the simulated
  seconds of one env-step (its physics runs at 240 Hz, ``env_step_ratio`` x
  ``updates_per_step`` physics steps per action), read from the env.
- ``jsbsim``: the Cessna 172 model ``c172x`` that jsbsim ships, at 3000 ft and 100 kt, engine
  running, trimmed in level flight (``do_trim(1)``), then ``FGFDMExec.run()`` (one FDM step of
  ``get_delta_t()`` = 1/120 s) in a loop; reported: FDM steps/s and the step's seconds.
"""

from __future__ import annotations

import json
import os
import sys
import time


def pyflyt(seconds: float, repeats: int) -> dict:
    import gymnasium as gym
    import numpy as np
    import PyFlyt
    import PyFlyt.gym_envs  # noqa: F401  (registers the envs)

    env_id = "PyFlyt/Fixedwing-Waypoints-v3"
    env = gym.make(env_id)
    rng = np.random.default_rng(0)
    space = env.action_space
    acts = [rng.uniform(space.low, space.high).astype(space.dtype) for _ in range(64)]
    env.reset(seed=0)
    inner = env.unwrapped
    aviary = inner.env
    step_s = inner.env_step_ratio * aviary.updates_per_step / aviary.physics_hz
    for a in acts:  # warm-up
        _, _, term, trunc, _ = env.step(a)
        if term or trunc:
            env.reset()
    best = None
    for _ in range(repeats):
        steps, resets, reset_s, t0 = 0, 0, 0.0, time.perf_counter()
        while (elapsed := time.perf_counter() - t0) < seconds:
            for a in acts:
                _, _, term, trunc, _ = env.step(a)
                if term or trunc:
                    t1 = time.perf_counter()
                    env.reset()
                    reset_s += time.perf_counter() - t1
                    resets += 1
            steps += len(acts)
        run = {"steps": steps, "wall_s": elapsed, "resets": resets, "reset_s": reset_s}
        if best is None or steps / elapsed > best["steps"] / best["wall_s"]:
            best = run
    env.close()
    return {
        "peer": "pyflyt",
        "what": env_id,
        "version": PyFlyt.__version__ if hasattr(PyFlyt, "__version__") else "0.29.0",
        "step_s": step_s,
        "rate": best["steps"] / best["wall_s"],
        "rate_steps_only": best["steps"] / (best["wall_s"] - best["reset_s"]),
        **best,
    }


def jsbsim_run(seconds: float, repeats: int) -> dict:
    import jsbsim

    fdm = jsbsim.FGFDMExec(jsbsim.get_default_root_dir())
    fdm.set_debug_level(0)
    fdm.load_model("c172x")
    fdm["ic/h-sl-ft"] = 3000.0
    fdm["ic/vc-kts"] = 100.0
    fdm["ic/gamma-deg"] = 0.0
    fdm["ic/psi-true-deg"] = 0.0
    fdm.run_ic()
    fdm["propulsion/set-running"] = -1  # all engines
    fdm["fcs/mixture-cmd-norm"] = 1.0
    fdm["fcs/throttle-cmd-norm"] = 0.7
    fdm.do_trim(1)  # full trim, level flight; raises if it fails
    trim = {
        "throttle": fdm["fcs/throttle-cmd-norm"],
        "elevator": fdm["fcs/elevator-cmd-norm"],
        "alpha_deg": fdm["aero/alpha-deg"],
    }
    step_s = fdm.get_delta_t()
    for _ in range(1200):  # warm-up: 10 s of flight
        fdm.run()
    h0, t_sim0 = fdm["position/h-sl-ft"], fdm.get_sim_time()
    best = None
    chunk = 200
    for _ in range(repeats):
        steps, t0 = 0, time.perf_counter()
        while (elapsed := time.perf_counter() - t0) < seconds:
            for _ in range(chunk):
                fdm.run()
            steps += chunk
        if best is None or steps / elapsed > best["steps"] / best["wall_s"]:
            best = {"steps": steps, "wall_s": elapsed}
    flown = fdm.get_sim_time() - t_sim0
    return {
        "peer": "jsbsim",
        "what": "FGFDMExec c172x, trimmed level flight, run()",
        "version": jsbsim.__version__,
        "step_s": step_s,
        "rate": best["steps"] / best["wall_s"],
        "altitude_change_ft": fdm["position/h-sl-ft"] - h0,
        "flown_s": flown,
        "trim": trim,
        **best,
    }


def main() -> None:
    peer, seconds, repeats = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
    runs = {"pyflyt": pyflyt, "jsbsim": jsbsim_run}
    if peer not in runs:
        raise SystemExit(f"unknown peer {peer!r}: expected one of {sorted(runs)}")
    result = runs[peer](seconds, repeats)
    result["pid"] = os.getpid()
    print("RESULT " + json.dumps(result), flush=True)


if __name__ == "__main__":
    main()

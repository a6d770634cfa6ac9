"""Evaluate a training run beside the scripted pilot and a random policy: see
``fluidsim_envs/rl/evaluate.py``.

    python training/evaluate.py runs/PaperAirplane-v0-ppo-20250101-120000 --episodes 100
"""

import sys

from fluidsim_envs.rl.evaluate import main

if __name__ == "__main__":
    sys.exit(main())

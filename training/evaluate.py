"""Evaluate a run folder: ``fluidsim-evaluate`` from a checkout (see
``fluidsim_envs/rl/evaluate.py``).

python training/evaluate.py runs/demo --model best --episodes 256 --rerun runs/demo/episodes.rrd
python training/evaluate.py --env-id fluidsim/BoatOnStep-v0 --episodes 256 --out runs/baselines
"""

import sys

from fluidsim_envs.rl.cli import evaluate

if __name__ == "__main__":
    sys.exit(evaluate())

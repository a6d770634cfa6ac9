"""Seeds and hyperparameter searches on Ray Tune: ``fluidsim-sweep`` from a checkout (see
``fluidsim_envs/rl/sweep.py``).

python training/sweep.py paper_airplane_ppo --seeds 5
python training/sweep.py paper_airplane_ppo --search space.yaml --trials 16
python training/sweep.py --resume sweeps/PaperAirplane-v1-ppo-20261203-140000
"""

import sys

from fluidsim_envs.rl.cli import sweep

if __name__ == "__main__":
    sys.exit(sweep())

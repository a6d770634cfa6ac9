"""Train a pilot from a YAML config: ``fluidsim-train`` from a checkout (see
``fluidsim_envs/rl/train.py``).

python training/train.py paper_airplane_ppo --set total_timesteps=100000
python training/train.py --resume runs/PaperAirplane-v0-ppo-20250101-120000
"""

import sys

from fluidsim_envs.rl.cli import train

if __name__ == "__main__":
    sys.exit(train())

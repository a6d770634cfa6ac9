"""Train a pilot from a YAML config: see ``fluidsim_envs/rl/train.py``.

python training/train.py configs/paper_airplane_ppo.yaml --set total_timesteps=100000
python training/train.py --resume runs/PaperAirplane-v0-ppo-20250101-120000
"""

import sys

from fluidsim_envs.rl.train import main

if __name__ == "__main__":
    sys.exit(main())

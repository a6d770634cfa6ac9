"""Training and evaluation with Stable-Baselines3: typed YAML configs (:mod:`.config`), the
training run (:mod:`.train`) and the evaluation of a run folder (:mod:`.evaluate`). The
scripts in ``training/`` call into these modules."""

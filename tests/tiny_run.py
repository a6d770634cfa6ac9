"""A tiny training run for the tests that read what a run writes."""


def train_tiny(folder, config: str, *sets: str):
    """``folder``, a run of the shipped ``config`` trained in-process on the ``--set`` items
    ``sets`` (a few hundred steps: what a test of the files a run writes needs)."""
    from fluidsim_envs.rl import train as train_cli

    argv = [config, "--set", *sets, "--run-dir", str(folder), "--no-progress-bar"]
    assert train_cli.main(argv) == 0
    return folder

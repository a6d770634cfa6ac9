"""The optional extras the commands need, checked before anything imports them: a missing one
is an error that says which ``pip install`` fixes it, not a bare ``ModuleNotFoundError``."""

from __future__ import annotations

import importlib.util

#: each extra of pyproject.toml and the modules the commands import from it
EXTRAS = {
    "train": (
        "stable_baselines3",
        "torch",
        "yaml",
        "tensorboard",
        "tqdm",
        "rich",
        "scipy",
        "safetensors",
    ),
    "rerun": ("rerun",),
    "tune": ("optuna",),
    "sweep": ("ray", "optuna", "pandas", "pyarrow"),
    "play": ("pygame", "yaml"),
}


class MissingExtra(ImportError):
    """An optional dependency is not installed; the message names the ``pip install``."""


def require(extra: str, who: str, modules: tuple[str, ...] | None = None) -> None:
    """Raise :class:`MissingExtra` unless every module of ``extra`` can be imported, or with
    ``modules`` those of the extra's packages that ``who`` imports (``fluidsim-enjoy --video``:
    moviepy, which the ``play`` extra installs beside pygame)."""
    wanted = EXTRAS[extra] if modules is None else modules
    missing = [m for m in wanted if importlib.util.find_spec(m) is None]
    if missing:
        raise MissingExtra(
            f"{who} needs {', '.join(missing)} (the {extra!r} extra): "
            f'pip install "fluidsim-envs[{extra}]"'
        )


__all__ = ["EXTRAS", "MissingExtra", "require"]

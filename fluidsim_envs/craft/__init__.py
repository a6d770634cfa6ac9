"""Shipped crafts as TOML data files; load them with ``Craft.load(name)``.

The schema and its validation live in :mod:`fluidsim_envs.physics.craft`.
"""

from fluidsim_envs.physics.craft import available

__all__ = ["available"]

"""A scene's keyboard controls for ``python -m fluidsim_envs.play``: each action driven by two
keys (:class:`Axis`). Plain data, no pygame: the scenes declare theirs (``Scene.keys``) and
the tests check them without a window."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: how fast a held key moves its control, in full ranges ([-1, 1] is two) per second
RATE_PER_S = 2.0


@dataclass(frozen=True)
class Axis:
    """One action driven by two keys (pygame key names): ``down`` lowers it, ``up`` raises
    it. A ``spring`` axis (a control surface) returns to 0 when neither is held; otherwise (a
    throttle) it holds its value.

    >>> stick = Axis("elevator", "up", "down")
    >>> stick.step(0.0, down=False, up=True, dt_s=0.1), stick.step(0.3, False, False, 0.1)
    (0.2, 0.1)
    """

    action: str
    down: str
    up: str
    spring: bool = True

    def step(self, value: float, down: bool, up: bool, dt_s: float) -> float:
        """The axis's value after ``dt_s`` seconds with these keys held."""
        move = RATE_PER_S * dt_s
        if up != down:
            return float(np.clip(value + (move if up else -move), -1.0, 1.0))
        if self.spring:
            return round(float(np.sign(value) * max(abs(value) - move, 0.0)), 12)
        return value

    def describe(self) -> str:
        hold = "springs back" if self.spring else "stays where left"
        return f"{self.action:12s} {self.down.upper():>5s} / {self.up.upper():<5s} ({hold})"


__all__ = ["RATE_PER_S", "Axis"]

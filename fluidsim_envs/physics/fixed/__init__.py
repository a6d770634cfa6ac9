"""Fixed-point physics: ``Simulator(..., dtype="fixed32" | "fixed64", fraction_bits=14)``.

``format.py`` (the formats, the unit scale factors, packing), ``laws.py`` (the integer
arithmetic, force laws and step, once), ``kernel.py`` (the batch kernel), ``reference.py``
(the same laws run as plain Python on Python integers), ``simulator.py``
(:class:`FixedSimulator`, what ``Simulator`` returns for a fixed-point dtype).
"""

from .format import FORMATS, INTEGRATORS, Format, Units
from .simulator import FixedSimulator

__all__ = ["FORMATS", "INTEGRATORS", "FixedSimulator", "Format", "Units"]

"""The docs site's API reference (docs/api.md, mkdocstrings) reads the docstrings as Python
shows them: a griffe extension, named in mkdocs.yml.

- A class whose docstring is assigned at import (each v1 env's, written from its v0's by
  ``scenes/realism.py``'s ``v1_doc``) has none in its source: it is read from the class.
- The docstrings' Sphinx roles (``:class:`~.planner.Planner```, ``:data:`SCENES```,
  ``:meth:`step```) read as code spans, since mkdocstrings renders Markdown, not reST; a
  target with a leading ``~`` shows its last part, as Sphinx shows it, and a relative one
  loses its leading dots.
"""

from __future__ import annotations

import importlib
import inspect
import re
from typing import Any

from griffe import Docstring, Extension, Object

ROLE = re.compile(r":(?:py:)?[a-z]+:`(~?)\.*([^`]+)`")


def code_spans(text: str) -> str:
    """``text`` with every Sphinx role as a Markdown code span."""

    def span(m: re.Match) -> str:
        target = m.group(2)
        return f"`{target.rsplit('.', 1)[-1] if m.group(1) else target}`"

    return ROLE.sub(span, text)


def runtime_docstring(obj: Object) -> str | None:
    """The docstring a class set on itself at import (None if it has none of its own, or its
    module does not import)."""
    try:
        cls = getattr(importlib.import_module(obj.module.path), obj.name)
    except (ImportError, AttributeError):
        return None
    own = cls.__dict__.get("__doc__") if isinstance(cls, type) else None
    return inspect.cleandoc(own) if own else None


class Docstrings(Extension):
    """Fills in the docstrings set at import and rewrites the roles (:func:`code_spans`)."""

    def on_instance(self, *, obj: Object, **kwargs: Any) -> None:
        if obj.docstring is None and obj.is_class:
            value = runtime_docstring(obj)
            if value is not None:
                obj.docstring = Docstring(value, parent=obj)
        if obj.docstring is not None:
            obj.docstring.value = code_spans(obj.docstring.value)

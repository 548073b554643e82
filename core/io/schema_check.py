"""A fast yes/no check of a JSON document against one of the shipped schemas, without jsonschema.

The scene reader asks this first: when a document is valid (the common case, and every check of
an edit), importing and running jsonschema (about 50 ms to import) is not needed. When it says
no, the reader runs jsonschema to word the problems exactly as before, so what users read is
jsonschema's message. The two must agree on acceptance; tests/core/test_schema_check.py checks
that on every example and on random mutations of them (hypothesis).

Only the JSON Schema 2020-12 keywords our schemas use are implemented, with jsonschema's
semantics (a float with an integral value is an ``integer``; ``True`` is not the number 1 for
``enum``/``const``; ``pattern`` is ``re.search``). A schema using any other keyword is refused at
compile time (:class:`Unsupported`), and the caller then always uses jsonschema for it.
"""
from __future__ import annotations

import re
from typing import Any, Callable

Check = Callable[[Any], bool]

#: keywords that do not constrain an instance
_ANNOTATIONS = frozenset({"description", "title", "$schema", "$id", "$comment", "examples", "default"})


class Unsupported(ValueError):
    """The schema uses a keyword (or a form of one) this checker does not implement."""


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


_TYPES: dict[str, Check] = {
    "object": lambda x: isinstance(x, dict),
    "array": lambda x: isinstance(x, list),
    "string": lambda x: isinstance(x, str),
    "number": _is_number,
    "integer": lambda x: (isinstance(x, int) and not isinstance(x, bool)) or (isinstance(x, float) and x.is_integer()),
    "boolean": lambda x: isinstance(x, bool),
    "null": lambda x: x is None,
}


def _equal_to(value: Any) -> Check:
    """jsonschema's ``equal`` against a scalar ``value`` (bool and numbers kept apart)."""
    if isinstance(value, str):
        return lambda x: isinstance(x, str) and x == value
    if isinstance(value, bool):
        return lambda x: x is value
    if value is None:
        return lambda x: x is None
    if _is_number(value):
        return lambda x: _is_number(x) and x == value
    raise Unsupported(f"enum/const value {value!r}")


def compile_schema(schema: Any) -> Check:
    """A function telling whether an instance is valid against ``schema`` (a dict with local
    references already inlined). Raises :class:`Unsupported` for keywords not implemented."""
    if schema is True:
        return lambda x: True
    if schema is False:
        return lambda x: False
    if not isinstance(schema, dict):
        raise Unsupported(f"schema {schema!r}")
    checks: list[Check] = []
    keys = set(schema) - _ANNOTATIONS
    for key in keys:
        value = schema[key]
        if key == "type":
            names = [value] if isinstance(value, str) else value
            if not isinstance(names, list) or not all(n in _TYPES for n in names):
                raise Unsupported(f"type {value!r}")
            fns = [_TYPES[n] for n in names]
            checks.append(fns[0] if len(fns) == 1 else (lambda x, fns=fns: any(f(x) for f in fns)))
        elif key in ("minimum", "maximum"):
            if not _is_number(value):
                raise Unsupported(f"{key} {value!r}")
            checks.append((lambda x, v=value: not _is_number(x) or not x < v) if key == "minimum"
                          else (lambda x, v=value: not _is_number(x) or not x > v))
        elif key in ("minItems", "maxItems", "minLength", "maxLength"):
            if not isinstance(value, int) or isinstance(value, bool):
                raise Unsupported(f"{key} {value!r}")
            kind = list if key.endswith("Items") else str
            if key.startswith("min"):
                checks.append(lambda x, v=value, k=kind: not isinstance(x, k) or len(x) >= v)
            else:
                checks.append(lambda x, v=value, k=kind: not isinstance(x, k) or len(x) <= v)
        elif key == "pattern":
            rx = re.compile(value)
            checks.append(lambda x, rx=rx: not isinstance(x, str) or rx.search(x) is not None)
        elif key == "enum":
            if not isinstance(value, list):
                raise Unsupported(f"enum {value!r}")
            fns = [_equal_to(v) for v in value]
            checks.append(lambda x, fns=fns: any(f(x) for f in fns))
        elif key == "const":
            checks.append(_equal_to(value))
        elif key == "required":
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise Unsupported(f"required {value!r}")
            checks.append(lambda x, req=tuple(value): not isinstance(x, dict) or all(r in x for r in req))
        elif key == "items":
            if "prefixItems" in schema:
                raise Unsupported("prefixItems")
            item = compile_schema(value)
            checks.append(lambda x, item=item: not isinstance(x, list) or all(item(v) for v in x))
        elif key == "properties":
            if not isinstance(value, dict):
                raise Unsupported(f"properties {value!r}")
            props = {name: compile_schema(sub) for name, sub in value.items()}

            def check_props(x, props=props):
                if not isinstance(x, dict):
                    return True
                for name, fn in props.items():
                    if name in x and not fn(x[name]):
                        return False
                return True
            checks.append(check_props)
        elif key == "additionalProperties":
            if "patternProperties" in schema:
                raise Unsupported("patternProperties")
            known = frozenset(schema.get("properties", {}))
            extra = compile_schema(value)
            checks.append(lambda x, known=known, extra=extra: not isinstance(x, dict) or
                          all(extra(v) for k, v in x.items() if k not in known))
        else:
            raise Unsupported(f"keyword {key!r}")
    if not checks:
        return lambda x: True
    if len(checks) == 1:
        return checks[0]
    return lambda x: all(c(x) for c in checks)

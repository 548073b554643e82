"""Which parts of an edited JSON document a schema check must look at again.

An edit of a scene element (a joint dragged, a length typed) changes a few leaves of its JSON
object. When the element's previous object was valid against its schema, and the schema is one
the fast checker compiles (:mod:`.schema_check`: only node-local keywords, no combinators), the
new object is valid exactly when every changed subtree is valid against its own subschema and
every unchanged node's own constraints still hold. Those hold when a dict keeps its key set and a
list its length: ``required``, ``additionalProperties`` (its keys), ``minItems``/``maxItems`` and
``type`` then give the same answers. :func:`changed_subtrees` finds the subtrees to check again.
"""
from __future__ import annotations

from typing import Any, Iterator

#: keywords whose answer for a dict or list node may change when only its children change
_VALUE_KEYWORDS = frozenset({"enum", "const"})


def changed_subtrees(schema: Any, old: Any, new: Any, path: str) -> Iterator[tuple[Any, Any, str]]:
    """Yield (subschema, new subtree, JSON path) for every maximal subtree of ``new`` that differs
    from ``old`` where the structure above it is unchanged (dicts with the same keys, lists of the
    same length). ``schema`` is an inlined schema (no ``$ref``); a node whose schema could depend
    on its children's values as a whole (``enum``/``const`` on a container) is yielded whole."""
    if old is new or (type(old) is type(new) and old == new and (not isinstance(new, (dict, list))
                                                                or repr(old) == repr(new))):
        return   # the reprs of containers too: ``==`` takes True for 1 and 1 for 1.0 inside them
    if isinstance(schema, dict) and not (_VALUE_KEYWORDS & schema.keys()):
        if isinstance(old, dict) and isinstance(new, dict) and old.keys() == new.keys():
            props = schema.get("properties", {})
            extra = schema.get("additionalProperties", True)
            for key, value in new.items():
                yield from changed_subtrees(props.get(key, extra), old[key], value, f"{path}.{key}")
            return
        if isinstance(old, list) and isinstance(new, list) and len(old) == len(new) and "prefixItems" not in schema:
            item = schema.get("items", True)
            for k, (a, b) in enumerate(zip(old, new)):
                yield from changed_subtrees(item, a, b, f"{path}[{k}]")
            return
    yield schema, new, path

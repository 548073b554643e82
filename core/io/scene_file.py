"""Scene files: read (tagged, migrated, then validated — in that order), write atomically.

Every problem found is reported with its JSON path and the id involved; nothing raises a
traceback at the user. ``load_scene`` raises :class:`SceneFormatError` listing all problems.
"""
from __future__ import annotations

import functools
import json
import math
import os
import stat
import sys
from pathlib import Path
from typing import Any, Callable

from mechsketch import resources  # a data package (example scenes, schemas): no code of ours above core

from ..errors import Problem, SceneFormatError
from ..model.kinds import element_kind
from ..model.scene import FORMAT, SCHEMA_VERSION, Scene
from .atomic import atomic_write_text  # noqa: F401  (re-exported: others import it from here)
from .schema_check import Check, Unsupported, compile_schema
from .schema_delta import changed_subtrees

#: files larger than this are refused before reading (bytes)
MAX_FILE_BYTES = 10 * 1024 * 1024


def _v1_to_v2(doc: dict) -> dict:
    """Version 1 -> 2: every linkage driver was a crank at constant speed; version 2 says so
    (``"kind": "crank"``). Runs before validation, so it touches only what has the expected shape
    and leaves anything else for the schema to report."""
    out = dict(doc)
    elements = doc.get("elements")
    if isinstance(elements, list):
        out["elements"] = []
        for ed in elements:
            if isinstance(ed, dict) and ed.get("type") == "linkage" and isinstance(ed.get("driver"), dict):
                ed = dict(ed)
                ed["driver"] = {"kind": "crank", **ed["driver"]}
            out["elements"].append(ed)
    out["schema_version"] = 2
    return out


def _v2_to_v3(doc: dict) -> dict:
    """Version 2 -> 3: the identity but for the number. Version 3 adds optional content only (a
    linkage's ``drawing`` block of plate sizes; new element kinds such as ``underlay``), so a
    version 2 document is already a valid version 3 one."""
    return {**doc, "schema_version": 3}


#: migrations: version v -> function turning a v document into a v+1 document
MIGRATIONS: dict[int, Callable[[dict], dict]] = {1: _v1_to_v2, 2: _v2_to_v3}


@functools.lru_cache(maxsize=None)
def _schema(name: str) -> dict:
    """A shipped schema (read once; not to be modified)."""
    return resources.schema(name)


def _inline_refs(node: Any, defs: dict) -> Any:
    """``node`` with every local ``{"$ref": "#/$defs/x", ...}`` replaced by a copy of ``x`` (its
    own keys, e.g. a description, kept): the validator then skips the reference machinery."""
    if isinstance(node, dict):
        ref = node.get("$ref")
        if isinstance(ref, str) and ref.startswith("#/$defs/") and ref[8:] in defs:
            target = _inline_refs(defs[ref[8:]], defs)
            return {**target, **{k: _inline_refs(v, defs) for k, v in node.items() if k != "$ref"}}
        return {k: _inline_refs(v, defs) for k, v in node.items()}
    if isinstance(node, list):
        return [_inline_refs(v, defs) for v in node]
    return node


@functools.lru_cache(maxsize=None)
def _flat_schema(name: str) -> dict:
    """A shipped schema with its local references inlined (built once; not to be modified)."""
    schema = _schema(name)
    return _inline_refs({k: v for k, v in schema.items() if k != "$defs"}, schema.get("$defs", {}))


@functools.lru_cache(maxsize=None)
def _fast_check(name: str) -> Check | None:
    """The yes/no check of a shipped schema (:mod:`.schema_check`), None if it uses a keyword the
    check does not implement (jsonschema then checks every document against it)."""
    try:
        return compile_schema(_flat_schema(name))
    except Unsupported:
        return None


@functools.lru_cache(maxsize=None)
def _validator(name: str):
    """The compiled jsonschema validator of a shipped schema (built once; local references
    inlined, which makes an edit's check of a 66-joint linkage 1.6x faster). jsonschema is
    imported here, when a document is to be explained, not when the module is."""
    import jsonschema

    return jsonschema.Draft202012Validator(_flat_schema(name))


#: longest message text kept from a schema error (they quote the offending value)
MAX_MESSAGE = 240


def _parse_json(text: str) -> tuple[Any, list[Problem]]:
    """Parse JSON text. NaN/Infinity are read as floats so that the finite check can name their
    JSON path and id; syntax errors name the line and column; deep nesting is a problem."""
    try:
        return json.loads(text, parse_constant=float), []
    except RecursionError:
        return None, [Problem("$", "JSON nested too deeply")]
    except ValueError as exc:  # json.JSONDecodeError, or an integer literal of > 4300 digits
        line = getattr(exc, "lineno", None)
        where = f" (line {line}, column {exc.colno})" if line else ""
        msg = exc.msg if hasattr(exc, "msg") else str(exc)
        return None, [Problem("$", f"not valid JSON{where}: {msg}")]


def _json_path(parts) -> str:
    out = "$"
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else f".{p}"
    return out


def _own_id(obj: Any, inherited: str | None) -> str | None:
    """The id a problem inside ``obj`` is about: obj's own string id, else the enclosing one."""
    if isinstance(obj, dict) and isinstance(obj.get("id"), str):
        return obj["id"]
    return inherited


def _nonfinite(obj: Any, path: str, out: list[Problem], id: str | None = None) -> None:
    """Report NaN, ±Infinity, subnormal coordinates (items of lists: they make cmath.phase and
    other math functions raise range errors; scalars have their own smallest values in the
    parsers) and integers too large for a float, with their path and the id of
    the innermost object carrying one (iterative: deep nesting cannot overflow the stack)."""
    stack = [(obj, path, id)]
    while stack:
        obj, path, id = stack.pop()
        if isinstance(obj, float) and not math.isfinite(obj):
            out.append(Problem(path, f"number must be finite, got {obj}", id))
        elif isinstance(obj, float) and 0.0 < abs(obj) < sys.float_info.min and path.endswith(("[0]", "[1]")):
            out.append(Problem(path, f"coordinate {obj!r} is subnormal (nonzero but below "
                                     f"{sys.float_info.min:.4g} mm in size): write 0 or a larger value", id))
        elif isinstance(obj, int) and not isinstance(obj, bool) and abs(obj) > sys.float_info.max:
            out.append(Problem(path, f"number must be finite, got an integer of {len(str(abs(obj)))} digits "
                                     "(too large for a float)", id))
        elif isinstance(obj, dict):
            inner = _own_id(obj, id)
            stack.extend((v, f"{path}.{k}", inner) for k, v in reversed(list(obj.items())))
        elif isinstance(obj, list):
            stack.extend((v, f"{path}[{i}]", id) for i, v in reversed(list(enumerate(obj))))


def _schema_problems(schema: dict | str, data: Any, base: str, id: str | None) -> list[Problem]:
    """Schema findings (``schema``: a dict, or the name of a shipped schema), each with its JSON
    path and the id of the innermost object carrying one. A valid document against a shipped
    schema is recognised without jsonschema (:func:`_fast_check`); jsonschema words the problems."""
    if isinstance(schema, str):
        fast = _fast_check(schema)
        if fast is not None and fast(data):
            return []
        validator = _validator(schema)
    else:
        import jsonschema

        validator = jsonschema.Draft202012Validator(schema)
    out = []
    for err in sorted(validator.iter_errors(data), key=lambda e: list(map(str, e.absolute_path))):
        where = base + _json_path(err.absolute_path)[1:]
        msg = err.message
        if err.validator == "additionalProperties":
            msg = msg.replace("Additional properties are not allowed", "unknown key(s)")
        elif err.validator == "pattern" and isinstance(err.schema, dict) and err.schema.get("description"):
            msg = f"{err.instance!r} is not {err.schema['description']}"   # not the regex itself
        if len(msg) > MAX_MESSAGE:  # keep the head (quoted value) and the tail (what is wrong)
            msg = msg[:MAX_MESSAGE // 2] + " … " + msg[-MAX_MESSAGE // 2:]
        who, node = _own_id(data, id), data
        for key in err.absolute_path:
            try:
                node = node[key]
            except (KeyError, IndexError, TypeError):
                break
            who = _own_id(node, who)
        out.append(Problem(where, msg, who))
    return out


def migrate(doc: dict) -> dict:
    """Bring a tagged document up to :data:`SCHEMA_VERSION`, one version at a time (the input is not
    changed)."""
    version = doc["schema_version"]
    while version < SCHEMA_VERSION:
        doc = MIGRATIONS[version](doc)
        version = doc["schema_version"]
    return doc


def scene_from_dict(doc: Any, source: str = "scene") -> tuple[Scene | None, list[Problem]]:
    """Tag check, migration, validation; returns the scene (None if any problem) and problems."""
    if not isinstance(doc, dict):
        return None, [Problem("$", f"a scene must be a JSON object, got {type(doc).__name__}")]
    if doc.get("format") != FORMAT:
        return None, [Problem("$.format", f"not a mechsketch scene (format is {doc.get('format')!r}, "
                                          f"expected {FORMAT!r})")]
    version = doc.get("schema_version")
    if not isinstance(version, int) or isinstance(version, bool) or version < 1:
        return None, [Problem("$.schema_version", f"must be a whole number >= 1, got {version!r}")]
    if version > SCHEMA_VERSION:
        return None, [Problem("$.schema_version", f"the file is from a newer mechsketch (schema_version "
                                                  f"{version}; this version reads up to {SCHEMA_VERSION})")]
    doc = migrate(doc)
    problems: list[Problem] = []
    _nonfinite(doc, "$", problems)
    if problems:
        return None, problems
    problems = _schema_problems("scene.schema.json", doc, "$", None)
    if problems:
        return None, problems
    elements = []
    seen: dict[str, int] = {}
    for k, ed in enumerate(doc["elements"]):
        path = f"$.elements[{k}]"
        eid = ed["id"]
        if eid in seen:
            problems.append(Problem(f"{path}.id", f"duplicate element id {eid!r} (also elements[{seen[eid]}])", eid))
            continue
        seen[eid] = k
        kind = element_kind(ed["type"])
        if kind is None:
            problems.append(Problem(f"{path}.type", f"element type {ed['type']!r} is not supported by "
                                                    "this version of mechsketch", eid))
            continue
        found = _schema_problems(kind.schema, ed, path, eid)
        if found:
            problems.extend(found)
            continue
        element, found = kind.parse(ed, path)
        problems.extend(found)
        if element is not None:
            elements.append(element)
    if problems:
        return None, problems
    return Scene(tuple(elements)), []


def element_problems(element: Any) -> list[Problem]:
    """Every problem the scene reader would find in ``element`` (a record built in code, by an
    edit or a tool) if it were read from a file: its ``to_dict()`` goes through the same finite
    check, schema and parser. Empty list: the element is one a file may hold."""
    try:
        data = dump_element(element)
    except (OverflowError, ValueError, TypeError, AttributeError) as exc:
        return [Problem("$", f"cannot be written to a scene file: {exc}", getattr(element, "id", None))]
    return _data_problems(data)


def _data_problems(data: Any) -> list[Problem]:
    """Every problem of an element's JSON object read as a scene's only element."""
    doc = {"format": FORMAT, "schema_version": SCHEMA_VERSION, "units": "mm", "elements": [data]}
    return scene_from_dict(doc, f"element {data.get('id', '?') if isinstance(data, dict) else '?'}")[1]


def element_problems_since(element: Any, known: dict[str, Any] | None) -> tuple[list[Problem], dict[str, Any] | None]:
    """:func:`element_problems` of ``element`` knowing ``known``, the JSON object of a valid
    element (the same element before an edit; None: not known), and the element's own object
    (None when it cannot be written). The same answer and messages, faster for an edit: when
    the objects keep their type, id and structure, only the subtrees that changed are checked
    against the schema and for finite numbers (:mod:`.schema_delta`); the parser, which checks
    the meaning (ids, geometry), reads the whole element as always. Anything else, and any
    subtree found wrong, goes the whole way (:func:`element_problems`)."""
    try:
        data = dump_element(element)
    except (OverflowError, ValueError, TypeError, AttributeError):
        return element_problems(element), None
    return _data_problems_since(data, known), data


def _data_problems_since(data: dict[str, Any], known: dict[str, Any] | None) -> list[Problem]:
    """:func:`_data_problems` of ``data`` knowing the valid object ``known`` (see
    :func:`element_problems_since`)."""
    kind = element_kind(data.get("type")) if isinstance(data.get("type"), str) else None
    fast = _fast_check(kind.schema) if kind is not None and isinstance(kind.schema, str) else None
    if (known is None or fast is None or known.get("type") != data["type"]
            or known.get("id") != data.get("id") or not isinstance(data.get("id"), str)):
        return _data_problems(data)
    path = "$.elements[0]"
    found: list[Problem] = []
    for sub, node, where in changed_subtrees(_flat_schema(kind.schema), known, data, path):
        _nonfinite(node, where, found)   # any problem: the whole way words it
        if found or not _compiled(sub)(node):
            return _data_problems(data)
    return kind.parse(data, path)[1]


_COMPILED: dict[int, tuple[Any, Check]] = {}


def _compiled(schema: Any) -> Check:
    """The fast check of a subschema of a shipped (cached) schema, compiled once."""
    hit = _COMPILED.get(id(schema))
    if hit is None or hit[0] is not schema:
        hit = _COMPILED[id(schema)] = (schema, compile_schema(schema))
    return hit[1]


def _kind(mode: int) -> str:
    """What a non-regular file is, in words."""
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a plain file"


def read_scene_text(path: str | os.PathLike) -> tuple[Any, list[Problem]]:
    """Read and parse a scene file's JSON; returns (document, problems).

    Only a regular file is read (a device such as /dev/zero, a FIFO or a socket is refused
    before anything is read, without blocking), and at most :data:`MAX_FILE_BYTES` + 1 bytes of
    it whatever its size claims (a file that grows, a /proc file of size 0).
    """
    p = Path(path)
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        return None, [Problem("$", f"no such file: {p}")]
    except IsADirectoryError:
        return None, [Problem("$", f"{p} is a folder, not a scene file")]
    except OSError as exc:
        return None, [Problem("$", f"cannot read {p}: {exc.strerror or exc}")]
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            what = _kind(st.st_mode)
            if what == "a folder":
                return None, [Problem("$", f"{p} is a folder, not a scene file")]
            return None, [Problem("$", f"{p} is not a regular file ({what}): a scene file is a "
                                       "plain .json file")]
        limit = MAX_FILE_BYTES
        if st.st_size > limit:
            return None, [Problem("$", f"file is {st.st_size / 1e6:.1f} MB; scene files are limited to "
                                       f"{limit / 1e6:.0f} MB")]
        chunks, total = [], 0
        while total <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > limit:
            return None, [Problem("$", f"file is over {limit / 1e6:.0f} MB (it grew while being read); "
                                       f"scene files are limited to {limit / 1e6:.0f} MB")]
        raw = b"".join(chunks)
    except OSError as exc:
        return None, [Problem("$", f"cannot read {p}: {exc.strerror or exc}")]
    finally:
        os.close(fd)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        return None, [Problem("$", f"not UTF-8 text (byte {exc.start}): not a JSON scene file")]
    return _parse_json(text)


def validate_file(path: str | os.PathLike) -> list[Problem]:
    """Every problem of a scene file (empty list: the file is good)."""
    doc, problems = read_scene_text(path)
    if problems:
        return problems
    return scene_from_dict(doc, str(path))[1]


def load_scene(path: str | os.PathLike) -> Scene:
    """Load a scene file; raises :class:`SceneFormatError` naming every problem."""
    doc, problems = read_scene_text(path)
    if not problems:
        scene, problems = scene_from_dict(doc, str(path))
        if scene is not None:
            return scene
    raise SceneFormatError(problems, str(path))


def _text_too_large(text: str) -> Problem | None:
    """The problem of a scene text over :data:`MAX_FILE_BYTES` in UTF-8 (the files' limit), or
    None. A text of more characters than that is refused without encoding it; one that might be
    over (more than a quarter of the limit: a character is at most 4 bytes) is measured."""
    limit = MAX_FILE_BYTES
    size = len(text)
    if limit // 4 < size <= limit:
        size = len(text.encode("utf-8", "surrogatepass"))
    if size <= limit:
        return None
    return Problem("$", f"scene text is {size / 1e6:.1f} MB; scenes are limited to {limit / 1e6:.0f} MB "
                        "(as scene files): not read")


def loads_scene(text: str, source: str = "scene") -> Scene:
    """Parse scene JSON text (see :func:`load_scene`); text over :data:`MAX_FILE_BYTES` in UTF-8
    is refused before it is parsed, as a file would be."""
    big = _text_too_large(text)
    if big is not None:
        raise SceneFormatError([big], source)
    doc, problems = _parse_json(text)
    if problems:
        raise SceneFormatError(problems, source)
    scene, problems = scene_from_dict(doc, source)
    if scene is None:
        raise SceneFormatError(problems, source)
    return scene


def dump_element(element: Any) -> dict[str, Any]:
    """An element's JSON object, written by its kind (:data:`~..model.kinds.ELEMENT_KINDS`)."""
    kind = element_kind(element.type)
    if kind is None:
        raise TypeError(f"element {element.id!r} has type {element.type!r}, which no scene file can hold")
    return kind.dump(element)


def dumps_scene(scene: Scene) -> str:
    """The scene as JSON text (authored data only; nothing derived)."""
    doc = {"format": FORMAT, "schema_version": SCHEMA_VERSION, "units": "mm",
           "elements": [dump_element(e) for e in scene.elements]}
    return json.dumps(doc, indent=2, allow_nan=False) + "\n"


def save_scene(scene: Scene, path: str | os.PathLike) -> None:
    """Save atomically (temporary file, then rename); raises :class:`ExportError` on failure."""
    atomic_write_text(path, dumps_scene(scene))

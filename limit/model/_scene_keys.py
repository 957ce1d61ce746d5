"""Keys of a scene file that its schema does not know (a typo such as ``"frction"`` would
otherwise run silently with the default): found by walking the file beside
``blockscene-1.schema.json`` (``properties``, ``items``, ``$ref``, ``anyOf``/``oneOf``/
``allOf``). ``meta`` is free-form and not walked."""
from __future__ import annotations

import difflib
import json
from functools import lru_cache
from importlib import resources


@lru_cache(maxsize=1)
def _schema() -> dict:
    return json.loads(resources.files("limit").joinpath("blockscene-1.schema.json").read_text())


def _resolve(node: dict, root: dict) -> dict:
    while isinstance(node, dict) and "$ref" in node:
        ref = node["$ref"]
        if not ref.startswith("#/"):
            return {}
        for part in ref[2:].split("/"):
            root_part = root.get(part) if isinstance(root, dict) else None
            root = root_part if root_part is not None else {}
        node, root = root, _schema()
    return node if isinstance(node, dict) else {}


def _properties(node: dict, root: dict) -> tuple[dict | None, list]:
    """(properties known at this object node, or None when any key is allowed; the sub-schemas
    that may apply to the same value)."""
    node = _resolve(node, root)
    alts = [node] + [_resolve(a, root) for k in ("anyOf", "oneOf", "allOf") for a in node.get(k, [])]
    props, open_ = {}, False
    for a in alts:
        if "properties" in a:
            props.update(a["properties"])
        if a.get("additionalProperties") not in (None, False) or a.get("patternProperties"):
            open_ = True
    return (None if open_ or not props else props), alts


def unknown_keys(data) -> list[tuple[tuple, str, str | None]]:
    """[(path of the object, unknown key, closest known key or None)] of a parsed scene."""
    root = _schema()
    out = []

    def walk(value, node, path):
        props, alts = _properties(node, root)
        if isinstance(value, dict):
            if props is not None:
                for key in value:
                    if key not in props:
                        close = difflib.get_close_matches(key, list(props), n=1)
                        out.append((path, key, close[0] if close else None))
            for key, sub in value.items():
                if key == "meta" and path == ():
                    continue
                for a in alts:
                    if key in a.get("properties", {}):
                        walk(sub, a["properties"][key], path + (key,))
                        break
        elif isinstance(value, list):
            for a in alts:
                if "items" in a and isinstance(a["items"], dict):
                    for i, sub in enumerate(value):
                        walk(sub, a["items"], path + (i,))
                    break

    walk(data, root, ())
    return out

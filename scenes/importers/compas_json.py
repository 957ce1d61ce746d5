"""compas JSON: block meshes saved by the compas framework (compas.json_dump, or a
compas_dem ``BlockModel``), one block per mesh.

compas serialises a ``compas.datastructures/Mesh`` as ``{"dtype" (compas 2) or "datatype"
(compas 1): "compas.datastructures/Mesh", "data": {"vertex": {key: {"x", "y", "z", ...}},
"face": {key: [vertex keys]}, "attributes": {"name": ...}, ...}}``, and a ``BlockModel`` keeps
one such mesh per element, under the element's ``geometry``. Reading those files through compas
itself needs the very versions (and, for a BlockModel, compas_dem) that wrote them; only the mesh
data matters here, so the file is read with :mod:`json` and every mesh found in it, at any
depth (a bare list of meshes too), outside the model's contacts (:data:`SKIP_KINDS`), becomes a block named after the mesh's ``name`` attribute,
else its element's name, else its position in the file.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from limit.errors import SceneError

from .readers import RawBlock, _clean


#: serialised objects whose meshes are not blocks (a BlockModel's interactions: contact polygons)
SKIP_KINDS = ("Contact", "Interaction")


def is_mesh_data(node) -> bool:
    """A compas Mesh's data: a dict whose ``vertex`` and ``face`` are dicts."""
    return isinstance(node, dict) and isinstance(node.get("vertex"), dict) and isinstance(node.get("face"), dict)


def _meshes(node, where: str, name_hint: str | None, out: list) -> None:
    """Append (mesh data, name, where) of every mesh under ``node`` in document order."""
    if isinstance(node, dict):
        kind = str(node.get("dtype") or node.get("datatype") or "")
        if any(w in kind for w in SKIP_KINDS):  # a contact's polygon is no block
            return
        if is_mesh_data(node):
            attrs = node.get("attributes") if isinstance(node.get("attributes"), dict) else {}
            out.append((node, attrs.get("name") if attrs.get("name") not in (None, "Mesh") else name_hint, where))
            return
        if is_mesh_data(node.get("data")):
            _meshes(node["data"], where, name_hint, out)
            return
        hint = name_hint
        if isinstance(node.get("data"), dict) and isinstance(node["data"].get("name"), str):
            hint = node["data"]["name"] if node["data"]["name"] not in ("Block", "Mesh") else hint
        for k, v in node.items():
            _meshes(v, f"{where}/{k}", k if k.count("-") == 4 and hint is None else hint, out)
    elif isinstance(node, list):
        for k, v in enumerate(node):
            _meshes(v, f"{where}/{k}", name_hint, out)


def read_compas_json(path: Path) -> list[RawBlock]:
    """Blocks of a compas JSON file: one per mesh (see the module docstring). SceneError naming
    the file, and the mesh, for a file with no mesh or a mesh with a face on a missing vertex."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise SceneError(f"{path}: not a JSON file ({exc})") from None
    found: list = []
    _meshes(doc, "", None, found)
    if not found:
        raise SceneError(f"{path}: no compas mesh in it (a dict with 'vertex' and 'face' tables)")
    out = []
    for k, (data, name, where) in enumerate(found):
        label = name or f"mesh{k}"
        keys = list(data["vertex"])
        try:
            V = np.array([[float(data["vertex"][v][c]) for c in "xyz"] for v in keys], dtype=float).reshape(-1, 3)
        except (KeyError, TypeError, ValueError):
            raise SceneError(f"{path}: mesh '{label}' ({where or '/'}): a vertex without numeric x, y, z") from None
        index = {str(v): i for i, v in enumerate(keys)}
        faces = []
        for fk, f in data["face"].items():
            try:
                faces.append([index[str(v)] for v in f])
            except (KeyError, TypeError):
                raise SceneError(f"{path}: mesh '{label}', face {fk}: refers to a vertex the mesh does not have") from None
        out.append(RawBlock(_clean(str(label)), V, faces, f"{Path(path).name}:{label}"))
    return out

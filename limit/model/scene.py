"""Scene files (format ``blockscene/1``, docs/formats.md, 'Scene file'): reading and validation.

:func:`load_scene` turns a file (or an already parsed dict) into a :class:`Scene`
of validated blocks, or raises :class:`~limit.errors.SceneError` with one line
naming the key or block at fault. Structure and value ranges are checked with
the JSON schema ``blockscene-1.schema.json``; what a schema cannot say
(dimensions of vectors, unknown ids, degenerate or overlapping blocks) is
checked here.

Units: metres, kilograms, newtons, seconds.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from pathlib import Path

import numpy as np

from limit.geom import geometry
from limit.errors import SceneError
from limit.model import dims, load_checks, units

FORMAT = "blockscene/1"
DEFAULT_FRICTION = 0.6
DEFAULT_DENSITY = 2000.0
DEFAULT_THICKNESS = 1.0
#: Default geometric tolerance as a fraction of the scene's bounding-box diagonal.
RELATIVE_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Block:
    """One rigid block.

    ``volume`` in m^3 (2D: polygon area times the scene thickness), ``mass`` in kg,
    ``centroid`` (d,) in m. ``poly`` holds the vertices and the faces.
    """

    id: str
    index: int
    poly: geometry.Polytope
    fixed: bool
    density: float
    tags: tuple
    volume: float
    mass: float
    #: indices (into the block's dofs, see :attr:`Scene.ndof`) held at zero: a roller or a
    #: symmetry plane (e.g. ``("y", "rx", "rz")`` on the mirror plane y = 0 of a 3D scene)
    blocked: tuple = ()
    #: a compound block's convex parts (geometry.Polytope), which move as one rigid body; () for a
    #: convex block. ``poly`` is then their envelope (geometry.envelope): the hull of all their
    #: vertices with the union's measure and centroid.
    parts: tuple = ()

    @property
    def centroid(self) -> np.ndarray:
        return self.poly.centroid

    @property
    def pieces(self) -> tuple:
        """The convex pieces that make up the block: its parts, or its one polytope."""
        return self.parts or (self.poly,)


@dataclass
class Scene:
    """A validated scene: blocks plus load case.

    ``gravity`` (d,) m/s^2; ``thickness`` m (2D only, out-of-plane depth);
    ``tolerance`` m, the geometric tolerance used for contact detection;
    ``friction_pairs`` maps a sorted pair of block indices to its mu.
    ``dead`` and ``live`` are the load lists of the file, with block selections
    resolved to lists of block indices under the key ``"_blocks"``.
    """

    name: str
    dim: int
    gravity: np.ndarray
    friction: float
    thickness: float
    tolerance: float
    scale: float
    blocks: list
    friction_pairs: dict
    dead: list
    live: list
    expected: dict = field(default_factory=dict)
    meta: dict = field(default_factory=dict)
    data: dict = field(default_factory=dict)
    path: str | None = None
    sliding_faces: int | None = None   # 3D friction model declared by the scene (interfaces.sliding_faces)
    angle_tolerance: float | None = None  # degrees: tilted faces that still form a joint (interfaces.angle_tolerance)
    slide_fit: str | None = None
    demand: object = None              # limit.model.seismic_demand.Demand of the file's "demand", or None
    fc: float | None = None            # its confidence factor (demand.fc), or None
    symmetry: str = "none"             # "mirror": declared mirror-symmetric (limit.verdict.symmetry checks it)
    joint_groups: tuple = ()           # the file's "joints", resolved: limit.model.joint_groups.JointGroup
    ties: tuple = ()                   # the file's "ties", resolved: limit.model.ties.Tie

    @property
    def n_blocks(self) -> int:
        return len(self.blocks)

    @property
    def free(self) -> np.ndarray:
        """Indices of the free (non-fixed) blocks, in file order."""
        return np.array([b.index for b in self.blocks if not b.fixed], dtype=int)

    @property
    def n_fixed(self) -> int:
        return sum(b.fixed for b in self.blocks)

    @property
    def ndof(self) -> int:
        """Degrees of freedom per free block: 3 in 2D (ux, uy, rz), 6 in 3D."""
        return dims.ndof(self.dim)

    def block_index(self) -> dict:
        return {b.id: b.index for b in self.blocks}

    @property
    def total_mass(self) -> float:
        return float(sum(b.mass for b in self.blocks))

    def bbox(self) -> np.ndarray:
        """(2, d) array: lower and upper corner of all blocks, in m."""
        v = np.vstack([b.poly.vertices for b in self.blocks])
        return np.vstack([v.min(axis=0), v.max(axis=0)])


# ----------------------------------------------------------------------------
# Reading


#: names of the degrees of freedom a block may have ``blocked``
DOF_NAMES = {2: ("x", "y", "rz"), 3: ("x", "y", "z", "rx", "ry", "rz")}


def _blocked(bd: dict, i: int, dim: int) -> tuple:
    names = bd.get("blocked", [])
    if not isinstance(names, list):
        raise SceneError(f"blocks[{i}] (block '{bd['id']}').blocked: must be a list of dof names")
    out = []
    for nm in names:
        if nm not in DOF_NAMES[dim]:
            raise SceneError(f"blocks[{i}] (block '{bd['id']}').blocked: unknown dof {json.dumps(nm)} "
                             f"(one of {', '.join(DOF_NAMES[dim])} in {dim}D)")
        out.append(DOF_NAMES[dim].index(nm))
    return tuple(sorted(set(out)))


class _NonFinite:
    """Placeholder for NaN, Infinity or an overflowing number found while parsing."""

    def __init__(self, text):
        self.text = text


def _parse_float(text: str):
    value = float(text)
    return value if math.isfinite(value) else _NonFinite(text)


def read_json(path) -> dict:
    """Read a scene file as JSON, rejecting non-finite numbers with their key."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(f"{p}: no such file") from None
    except IsADirectoryError:
        raise SceneError(f"{p}: is a directory, not a scene file") from None
    except UnicodeDecodeError as exc:
        raise SceneError(f"{p}: not a UTF-8 text file ({exc.reason} at byte {exc.start})") from None
    except OSError as exc:
        raise SceneError(f"{p}: cannot read ({exc.strerror})") from None
    return parse_json(text, str(p))


def parse_json(text: str, where: str = "scene") -> dict:
    try:
        data = json.loads(text, parse_float=_parse_float, parse_constant=_NonFinite)
    except json.JSONDecodeError as exc:
        raise SceneError(f"{where}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
    except RecursionError:
        raise SceneError(f"{where}: JSON nested too deeply") from None
    except ValueError as exc:  # e.g. an integer with too many digits
        raise SceneError(f"{where}: not valid JSON ({exc})") from None
    if not isinstance(data, dict):
        raise SceneError(f"{where}: the top level must be a JSON object, not {type(data).__name__}")
    return data


def _find_nonfinite(node, path=()):
    if isinstance(node, _NonFinite):
        return path, node.text
    if isinstance(node, dict):
        items = node.items()
    elif isinstance(node, list):
        items = enumerate(node)
    else:
        return None
    for k, v in items:
        found = _find_nonfinite(v, path + (k,))
        if found:
            return found
    return None


def _where(path, data) -> str:
    """Readable location of a JSON path, naming the block by its id when known."""
    out = ""
    for i, key in enumerate(path):
        if isinstance(key, int):
            out += f"[{key}]"
            if i == 1 and path[0] == "blocks":
                try:
                    bid = data["blocks"][key]["id"]
                    if isinstance(bid, str):
                        out += f" (block '{bid}')"
                except (KeyError, IndexError, TypeError):
                    pass
        else:
            out += ("." if out else "") + str(key)
    return out or "scene"


@lru_cache(maxsize=1)
def _validator():
    import fastjsonschema

    schema = json.loads(resources.files("limit").joinpath("blockscene-1.schema.json").read_text())
    return fastjsonschema.compile(schema)


_JSON_TYPES = {dict: "object", list: "array", str: "string", bool: "boolean", int: "integer",
               float: "number", type(None): "null"}


def _schema_message(err, data) -> str:
    """One line for a fastjsonschema error, naming the key (and the block id)."""
    path = tuple(int(k) if k.isdigit() else k for k in err.path[1:])
    where = _where(path, data)
    rule, want, inst = err.rule, err.rule_definition, err.value
    shown = json.dumps(inst)[:40] if not isinstance(inst, _NonFinite) else inst.text
    if path == ("format",):
        return f"format: expected '{FORMAT}', got {shown}"
    if path == ("dim",):
        return f"dim: must be 2 or 3, got {shown}"
    if rule == "required":
        missing = [k for k in want if not (isinstance(inst, dict) and k in inst)]
        return f"{where}: missing required key{'s' if len(missing) > 1 else ''} {', '.join(map(repr, missing))}"
    if rule in ("enum", "const"):
        opts = want if isinstance(want, list) else [want]
        return f"{where}: unknown value {shown} (expected {' or '.join(map(json.dumps, opts))})"
    if rule == "type":
        want = " or ".join(want) if isinstance(want, list) else want
        return f"{where}: must be {want}, got {_JSON_TYPES.get(type(inst), type(inst).__name__)} {shown}"
    if rule in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"):
        rel = {"minimum": ">=", "exclusiveMinimum": ">", "maximum": "<=", "exclusiveMaximum": "<"}[rule]
        return f"{where}: {inst!r} is out of range (must be {rel} {want!r})"
    if rule == "minItems":
        return f"{where}: has {len(inst)} items, needs at least {want}"
    if rule == "maxItems":
        return f"{where}: has {len(inst)} items, at most {want} allowed"
    if rule == "anyOf" and path[-1:] == ("blocks",):
        return f"{where}: must be \"all\", a list of block ids or {{\"tags\": [...]}}"
    if rule == "minLength":
        return f"{where}: must not be empty"
    return f"{where}: {err.message.split(' ', 1)[-1]}"


# ----------------------------------------------------------------------------
# Validation and construction


def _unknown_keys(data: dict, strict: bool) -> None:
    import warnings

    from limit.errors import SceneWarning
    from limit.model._scene_keys import unknown_keys

    msgs = [f"{_where(path + (key,), data)}: unknown key" + (f" (did you mean '{near}'?)" if near else "")
            for path, key, near in unknown_keys(data)]
    if msgs and strict:
        raise SceneError("; ".join(msgs))
    for m in msgs:
        warnings.warn(m, SceneWarning, stacklevel=3)


def _demand(d: dict | None):
    """The file's "demand" as a :class:`limit.model.seismic_demand.Demand` (None without one); its
    rules beyond the schema's (TB < TC < TD; H, N and T1 with Z > 0) raise SceneError naming
    the key."""
    if d is None:
        return None
    from limit.model.seismic_demand import from_mapping

    try:
        return from_mapping(d)
    except ValueError as exc:
        raise SceneError(str(exc)) from None


def load_scene(source, check_overlaps: bool = True, strict: bool = False) -> Scene:
    """Read, validate and build a scene.

    ``source``: a path or an already parsed dict. Raises SceneError on any
    rejected input. ``check_overlaps`` runs the block-overlap test (on by default).
    A key the schema does not know gives a :class:`limit.errors.SceneWarning` naming it
    and the closest known key; with ``strict`` it is a SceneError.
    """
    if isinstance(source, dict):
        data, path = source, None
    else:
        path = str(source)
        data = read_json(source)
    where = path or "scene"
    found = _find_nonfinite(data)
    if found:
        p, text = found
        raise SceneError(f"{_where(p, data)}: non-finite number {text} (NaN, Infinity and overflowing values are not allowed)")
    import fastjsonschema

    if data.get("format") != FORMAT:
        shown = json.dumps(data["format"])[:40] if "format" in data else "nothing"
        raise SceneError(f"format: expected '{FORMAT}', got {shown}")
    try:
        _validator()(data)
    except fastjsonschema.JsonSchemaValueException as err:
        raise SceneError(_schema_message(err, data)) from None
    _unknown_keys(data, strict)
    data = units.to_metres(data)  # every length in metres from here on

    dim = int(data["dim"])
    name = data.get("name") or (Path(path).stem if path else "scene")
    gravity = np.array(data.get("gravity", [0.0, -9.81] if dim == 2 else [0.0, 0.0, -9.81]), dtype=float)
    _check_len(gravity, dim, "gravity")
    if not np.any(gravity):
        raise SceneError("gravity: must not be zero (self weight and body forces scale with it)")
    friction = float(data.get("friction", DEFAULT_FRICTION))
    density = float(data.get("density", DEFAULT_DENSITY))
    thickness = float(data.get("thickness", DEFAULT_THICKNESS))

    blocks_data = data["blocks"]
    ids = {}
    for i, bd in enumerate(blocks_data):
        bid = bd["id"]
        if bid in ids:
            raise SceneError(f"blocks[{i}]: duplicate block id '{bid}' (also blocks[{ids[bid]}])")
        ids[bid] = i

    pieces = [_block_pieces(bd, i, dim) for i, bd in enumerate(blocks_data)]
    polys = [geometry.envelope(ps) for ps in pieces]
    allv = np.vstack([p.vertices for p in polys])
    scale = float(np.linalg.norm(np.ptp(allv, axis=0)))
    tolerance = float(data.get("tolerance", RELATIVE_TOLERANCE * scale))

    blocks = []
    for i, (bd, poly, parts) in enumerate(zip(blocks_data, polys, pieces)):
        rho = float(bd.get("density", density))
        vol = poly.measure * (thickness if dim == 2 else 1.0)
        for k, part in enumerate(parts):
            what = f"blocks[{i}] (block '{bd['id']}')" + (f".parts[{k}]" if "parts" in bd else "")
            if part.measure <= (1e-9 * scale) ** dim:
                raise SceneError(f"{what}: degenerate block with no {'area' if dim == 2 else 'volume'}")
            # the width across each face (a convex block's least width is across one of its faces in 2D,
            # and at most that in 3D): a block thinner than the contact tolerance has no usable contact
            proj = part.vertices @ part.face_normals.T
            width = float(np.min(proj.max(axis=0) - proj.min(axis=0)))
            if width <= tolerance:
                raise SceneError(f"{what}: {width:.3g} m thin, not above the geometric "
                                 f"tolerance {tolerance:.3g} m")
        blocks.append(Block(bd["id"], i, poly, bool(bd.get("fixed", False)), rho,
                            tuple(bd.get("tags", ())), vol, rho * vol, _blocked(bd, i, dim),
                            tuple(parts) if "parts" in bd else ()))

    if not any(b.fixed for b in blocks):
        raise SceneError("blocks: no fixed block (at least one block needs \"fixed\": true to support the others)")
    if all(b.fixed for b in blocks):
        raise SceneError("blocks: every block is fixed: nothing can move (leave at least one without \"fixed\": true)")

    friction_pairs = {}
    for k, item in enumerate(data.get("interfaces", {}).get("friction", [])):
        a, b = item["blocks"]
        for j, x in enumerate((a, b)):
            if x not in ids:
                raise SceneError(f"interfaces.friction[{k}].blocks[{j}]: unknown block id '{x}'")
        if a == b:
            raise SceneError(f"interfaces.friction[{k}].blocks: a block cannot touch itself ('{a}')")
        friction_pairs[tuple(sorted((ids[a], ids[b])))] = float(item["mu"])

    from limit.model.joint_groups import parse_joint_groups

    joint_groups = parse_joint_groups(data.get("joints", []), ids, blocks, dim, tolerance)
    from limit.model.ties import parse_ties

    ties = parse_ties(data.get("ties", []), ids, blocks, dim, tolerance)
    loads = data.get("loads", {})
    dead = [_resolve_load(ld, f"loads.dead[{k}]", dim, ids, blocks) for k, ld in
            enumerate(loads.get("dead", [{"type": "self_weight"}]))]
    live = [_resolve_load(ld, f"loads.live[{k}]", dim, ids, blocks) for k, ld in enumerate(loads.get("live", []))]

    scene = Scene(name=name, dim=dim, gravity=gravity, friction=friction, thickness=thickness,
                  tolerance=tolerance, scale=scale, blocks=blocks, friction_pairs=friction_pairs,
                  dead=dead, live=live, expected=dict(data.get("expected", {})),
                  meta=dict(data.get("meta", {})), data=data, path=path,
                  sliding_faces=data.get("interfaces", {}).get("sliding_faces"),
                  slide_fit=data.get("interfaces", {}).get("slide_fit"),
                  angle_tolerance=data.get("interfaces", {}).get("angle_tolerance"),
                  demand=_demand(data.get("demand")), fc=(data.get("demand") or {}).get("fc"),
                  symmetry=data.get("symmetry", "none"), joint_groups=joint_groups, ties=ties)
    load_checks.check_loads(scene)
    if check_overlaps:
        from limit.geom.overlap import check_overlaps as _check

        _check(scene)
    return scene


def _check_len(vec, dim, where):
    if len(vec) != dim:
        raise SceneError(f"{where}: has {len(vec)} coordinates, a {dim}D scene needs {dim}")


def _block_pieces(bd: dict, i: int, dim: int) -> list:
    """The block's convex pieces (geometry.Polytope): one for a ``box`` or ``vertices`` block, one
    per entry of a compound block's ``parts``."""
    label = f"blocks[{i}] (block '{bd['id']}')"
    if sum(k in bd for k in ("box", "vertices", "parts")) != 1:
        raise SceneError(f"{label}: needs exactly one of 'box', 'vertices' or 'parts'")
    if "parts" not in bd:
        return [_block_polytope(bd, i, dim)]
    out = []
    for k, part in enumerate(bd["parts"]):
        for j, v in enumerate(part["vertices"]):
            _check_len(v, dim, f"{label}.parts[{k}].vertices[{j}]")
        try:
            out.append(geometry.polytope(part["vertices"], dim))
        except geometry.GeometryError as exc:
            raise SceneError(f"{label}.parts[{k}]: {exc}") from None
    return out


def _block_polytope(bd: dict, i: int, dim: int) -> geometry.Polytope:
    label = f"blocks[{i}] (block '{bd['id']}')"
    try:
        if "box" in bd:
            bx = bd["box"]
            _check_len(bx["center"], dim, f"{label}.box.center")
            _check_len(bx["size"], dim, f"{label}.box.size")
            rot = None
            if "rotation" in bx:
                r = bx["rotation"]
                if dim == 3 and "axis" not in r:
                    raise SceneError(f"{label}.box.rotation: missing 'axis' (a 3D rotation needs its axis)")
                rot = geometry.rotation_matrix(dim, r["angle_deg"], r.get("axis"))
            return geometry.box(bx["center"], bx["size"], rot)
        for k, v in enumerate(bd["vertices"]):
            _check_len(v, dim, f"{label}.vertices[{k}]")
        return geometry.polytope(bd["vertices"], dim)
    except geometry.GeometryError as exc:
        raise SceneError(f"{label}: {exc}") from None


def _resolve_load(ld: dict, where: str, dim: int, ids: dict, blocks: list) -> dict:
    """Copy of a load with its selection resolved to block indices (key '_blocks')."""
    out = dict(ld)
    t = ld["type"]
    if t == "point_force":
        if ld["block"] not in ids:
            raise SceneError(f"{where}.block: unknown block id '{ld['block']}'")
        _check_len(ld["force"], dim, f"{where}.force")
        if "point" in ld:
            _check_len(ld["point"], dim, f"{where}.point")
        out["_blocks"] = [ids[ld["block"]]]
        return out
    if t == "body_force":
        _check_len(ld["direction"], dim, f"{where}.direction")
    if t == "pressure":
        _check_len(ld["face"], dim, f"{where}.face")
        if not np.linalg.norm(np.asarray(ld["face"], dtype=float)) > 0:
            raise SceneError(f"{where}.face: the outward normal of the loaded faces must not be zero")
        for key in ("value", "gradient", "level"):
            v = ld.get(key, 0.0)
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v)):
                raise SceneError(f"{where}.{key}: a finite number, got {v!r}")
    sel = ld.get("blocks", "all")
    if sel == "all":
        idx = [b.index for b in blocks]
    elif isinstance(sel, list):
        idx = []
        for k, bid in enumerate(sel):
            if bid not in ids:
                raise SceneError(f"{where}.blocks[{k}]: unknown block id '{bid}'")
            idx.append(ids[bid])
    else:
        tags = set(sel["tags"])
        idx = [b.index for b in blocks if tags.intersection(b.tags)]
        if not idx:
            raise SceneError(f"{where}.blocks.tags: no block carries any of the tags {sorted(tags)}")
    out["_blocks"] = idx
    return out

"""Geometry: convex blocks, their clipping and overlap, and the interfaces (contacts) found
from it (:mod:`~limit.geom.interfaces`). Knows nothing of loads or solvers. Lengths in the
scene's units (m). Modules with a leading underscore (the broad phase, polygon clipping, the
face table) are internal: their names may change without notice."""

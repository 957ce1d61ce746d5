"""Geometry: convex blocks, their clipping and overlap, and the interfaces (contacts) found
from it. Knows nothing of loads or solvers. Lengths in the scene's units (m)."""

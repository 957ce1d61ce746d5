"""Readers that turn CAD and mesh files (OBJ, STL, PLY, DXF) into ``blockscene/1`` scenes."""

"""The model: the scene file read and checked (:mod:`~limit.model.scene`), its loads, the
kinematics of the interfaces, the yield domain (4 faces per 2D interface, 10 per 3D one,
after Baggio & Trovalusci) and the assembled LP data (:mod:`~limit.model.assemble`). Modules with a leading underscore are internal."""

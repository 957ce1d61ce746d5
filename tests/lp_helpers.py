"""Small helpers shared by the limit-analysis tests."""
from limit.analysis import solve_lp
from limit.model.assemble import Options, assemble
from limit.model.scene import load_scene


#: the solver lp_alpha uses when none is named (test modules may switch it, see test_lp_closed_form)
SOLVER = "clarabel"


def lp_alpha(scene_dict, solver=None, model="paper", check_kinematic=False, **opts):
    """(alpha, solution, residuals) of the associative LP for a scene dict (no fallback solver)."""
    solver = solver or SOLVER
    P = assemble(load_scene(scene_dict), Options(model=model, **opts))
    sol, attempts, res = solve_lp(P, solver, fallback=False, check_kinematic=check_kinematic)
    assert sol.status == "optimal", (sol.status, sol.reason, attempts)
    return sol.alpha, sol, res, P

"""A structured primal-dual interior point method for the static LP (step 1), for large scenes.

Solves the scaled static LP of :mod:`limit.solve.lp`::

    minimise -alpha  s.t.  Eh x + fLh alpha = -f0h,   Yh x + s = c,  s >= 0

(c = 0 for the LP of step 1; the iterative LP of step 2 moves the friction
capacities mu N* into c, :mod:`limit.solve.iterative_lp`, and may add a proximal term
``1/2 sum q (x - x_ref)^2`` to the objective: a convex QP, whose diagonal q joins the
interface blocks below)

with Mehrotra's predictor-corrector and Gondzio's centrality correctors (:data:`MCC`). Its
dual variables are the mechanism
``y`` (= the static LP's equality multipliers vh, with ``fLh . y = 1``) and
the plastic multipliers ``z`` (= lamh >= 0).

Why not a general solver: the yield rows of an interface only touch that
interface's own actions, so ``Yh.T D Yh`` (D = z / s) is block diagonal with
one small block per interface (3 x 3 in 2D, 6 x 6 in 3D). Eliminating the
slacks and the actions leaves one symmetric positive definite system per
iteration, ``N = Eh (Yh.T D Yh)^-1 Eh.T``, of the size of the block degrees of
freedom, which CHOLMOD (through cvxopt) factors. A general solver factors the
whole KKT system instead: Clarabel spends 0.32 s per iteration on a 10,000-block
2D wall where this needs about 0.1 s (``make bench``, bench/out/lp_summary.md).
The column of the live load (dense: every block) is kept out of N and
handled by a rank-one Schur complement.

The method has no infeasibility detection: when it does not converge, its
status is "failed" and :func:`limit.analysis.solve_lp` asks the next solver
(Clarabel), whose statuses cover unbounded and infeasible problems. Every
answer is verified a posteriori (:mod:`limit.solve.verify`) like any solver's.
Requires every interface's yield rows to span its actions (true for the
paper's and the vertex model: no action is free of all faces).
"""
from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp

from limit.solve.status import IpmStatus

#: regularisation of the interface blocks and of N, relative to their largest diagonal entry
REG_H = 1e-13
REG_N = 1e-16
#: the largest shift tried when a factorisation fails
REG_N_MAX = 1e-7
#: |alpha| (scaled problem) taken as divergence: the LP is probably unbounded
ALPHA_DIVERGED = 1e9
#: rounds of iterative refinement of each Newton step
REFINE = 3
#: ... of the predictor, which only sets the centring and the corrector's second-order term: none
#: (the same alphas, fewer seconds; docs/performance.md, 'Measurements moved from code comments')
REFINE_PREDICTOR = 0
#: Gondzio's centrality correctors per iteration (:func:`_centrality_correctors`) and their
#: parameters: two cut the step-1 LP's iterations by about a fifth (docs/performance.md,
#: 'Measurements moved from code comments')
MCC = 2
MCC_DELTA = 0.2
MCC_BETA_MIN = 0.1
MCC_BETA_MAX = 10.0
MCC_GAMMA = 0.1
#: warm start (:func:`solve`'s ``warm``): slacks and multipliers below WARM_SHIFT x their mean
#: in the given point are raised to it, back into the interior. Measured on the iterative LP of
#: a 3,052-block 2D wall (tolerance 1e-4, cold 31-40 iterations): 0.001 failed, 0.01 took 50-70
#: iterations, 0.1 25-33, 0.2 to 1 21-34
WARM_SHIFT = 1.0
#: ``almost`` (see :func:`_solve`): the method is taken as stalled once its largest relative
#: residual (primal, dual, gap) has had no new low for this many iterations
ALMOST_STALL = 30
#: a Newton step whose residual is below this (scaled units) is not refined (docs/decisions.md:
#: the looser stops tried)
REFINE_ABS = 1e-11


class _Blocks:
    """The yield rows of each interface as a dense block, grouped by the interface's number of
    actions k: per class ``Yd`` (n_interfaces, most faces, k), zero-padded, and where each face goes."""

    def __init__(self, Yh: sp.csr_matrix, x_group: np.ndarray):
        if np.any(np.diff(x_group) < 0):
            raise ValueError("interface actions must be stored interface by interface")
        Y = Yh.tocoo()
        n_x = Yh.shape[1]
        starts = np.flatnonzero(np.r_[True, x_group[1:] != x_group[:-1]])
        sizes = np.diff(np.r_[starts, n_x])
        group_of_x = np.repeat(np.arange(len(starts)), sizes)
        pos_in_group = np.arange(n_x) - np.repeat(starts, sizes)
        face_group = np.full(Yh.shape[0], -1)
        face_group[Y.row] = group_of_x[Y.col]
        if np.any(face_group[Y.row] != group_of_x[Y.col]):
            raise ValueError("a yield face couples the actions of two interfaces")
        self.classes = []
        rows, cols = [], []
        fsize = np.where(face_group >= 0, sizes[np.maximum(face_group, 0)], -1)
        for k in np.unique(sizes):
            gs = np.flatnonzero(sizes == k)
            slot = np.full(len(starts), -1)
            slot[gs] = np.arange(len(gs))
            faces = np.flatnonzero(fsize == k)
            fg = slot[face_group[faces]]
            order = np.argsort(fg, kind="stable")
            faces, fg = faces[order], fg[order]
            counts = np.bincount(fg, minlength=len(gs))
            frow = np.arange(len(faces)) - np.repeat(np.cumsum(counts) - counts, counts)
            fpos = np.full(Yh.shape[0], -1)
            fpos[faces] = np.arange(len(faces))
            nz = fpos[Y.row] >= 0
            Yd = np.zeros((len(gs), int(counts.max(initial=0)), k))
            Yd[fg[fpos[Y.row[nz]]], frow[fpos[Y.row[nz]]], pos_in_group[Y.col[nz]]] = Y.data[nz]
            xidx = starts[gs][:, None] + np.arange(k)[None, :]  # (ng, k) action indices
            self.classes.append((Yd, faces, fg, frow, xidx))
            rows.append(np.repeat(xidx, k, axis=1).ravel())
            cols.append(np.tile(xidx, (1, k)).ravel())
        self.n_x = n_x
        self.rows = np.concatenate(rows) if rows else np.empty(0, int)
        self.cols = np.concatenate(cols) if cols else np.empty(0, int)
        # the CSR structure of the block-diagonal inverse, fixed: only its values change
        tmpl = sp.csr_matrix((np.arange(1.0, self.rows.size + 1), (self.rows, self.cols)), shape=(n_x, n_x))
        tmpl.sort_indices()
        self._perm = tmpl.data.astype(np.int64) - 1
        self._indices, self._indptr = tmpl.indices, tmpl.indptr

    def inverse(self, d: np.ndarray, q: np.ndarray | None = None) -> list[np.ndarray]:
        """``(Yh.T diag(d) Yh + diag(q))^-1`` per interface: one (n_interfaces, k, k) array per
        class (q (n_x,) >= 0: the proximal weights of :func:`solve`; None: none)."""
        out = []
        for Yd, faces, fg, frow, xidx in self.classes:
            Dp = np.zeros(Yd.shape[:2])
            Dp[fg, frow] = d[faces]
            H = np.matmul(Yd.transpose(0, 2, 1) * Dp[:, None, :], Yd)  # Yd.T diag(d) Yd per interface
            if q is not None:
                k = Yd.shape[2]
                H[:, np.arange(k), np.arange(k)] += q[xidx]
            out.append(_spd_inverse(H))
        return out

    def matrix(self, hinv: list[np.ndarray]) -> sp.csr_matrix:
        """The block-diagonal sparse matrix (n_x, n_x) of :meth:`inverse`'s blocks."""
        vals = np.concatenate([h.ravel() for h in hinv]) if hinv else np.empty(0)
        return sp.csr_matrix((vals[self._perm], self._indices, self._indptr), shape=(self.n_x, self.n_x))


def _spd_inverse(H: np.ndarray) -> np.ndarray:
    """Inverses of the symmetric positive semi-definite blocks H (g, k, k), kept positive definite.

    Each block, shifted by REG_H of its largest diagonal entry, is inverted through its
    Cholesky factor L (H = L L.T, H^-1 = L^-T L^-1), column by column over all blocks at once
    (np.linalg.inv with a Cholesky check of its result: 32 ms per call at 10,050 2D blocks, this
    16 ms). A block whose pivot is not
    positive, or whose inverse is not finite, goes through its eigenvalues instead, clamped at
    REG_H of the largest."""
    g, k, _ = H.shape
    idx = np.arange(k)
    scale = np.abs(H[:, idx, idx]).max(axis=1, initial=0.0) if g else np.zeros(0)
    A = H.copy()
    A[:, idx, idx] += (REG_H * scale)[:, None]
    L = np.zeros_like(A)
    bad = np.zeros(g, dtype=bool)
    for j in range(k):
        piv = A[:, j, j] - np.einsum("gi,gi->g", L[:, j, :j], L[:, j, :j])
        bad |= ~(piv > 0.0)
        L[:, j, j] = np.sqrt(np.where(piv > 0.0, piv, 1.0))
        if j + 1 < k:
            L[:, j + 1:, j] = (A[:, j + 1:, j] - np.einsum("gik,gk->gi", L[:, j + 1:, :j], L[:, j, :j])) / L[:, j, j, None]
    W = np.zeros_like(A)  # W = L^-1, lower triangular, by forward substitution
    for j in range(k):
        W[:, j, j] = 1.0 / L[:, j, j]
        for i in range(j + 1, k):
            W[:, i, j] = -np.einsum("gm,gm->g", L[:, i, j:i], W[:, j:i, j]) / L[:, i, i]
    Hi = np.matmul(W.transpose(0, 2, 1), W)
    bad |= ~np.isfinite(Hi).all(axis=(1, 2))
    if bad.any():
        w, V = np.linalg.eigh(H[bad])
        w = np.maximum(w, REG_H * np.maximum(w[:, -1:], np.finfo(float).tiny))
        Hi[bad] = np.einsum("gak,gk,gbk->gab", V, 1.0 / w, V)
    return Hi


class _Reduced:
    """``N = Eh Hinv Eh.T + shift I`` (n_dof, n_dof), factored by CHOLMOD (via cvxopt) on a pattern fixed
    once, so that its symbolic analysis (the fill-reducing ordering) is done only once.

    N is summed interface by interface: the columns of Eh of one interface's actions touch only
    the block unknowns of its two blocks (w of them), so with ``Ed`` (n_interfaces, w, k) those
    columns, dense, each interface adds ``Ed Hinv_i Ed.T`` (w x w) to N, and where each entry goes
    in the factor's value array is found once. (Two sparse products Eh Hinv Eh.T took 4 times
    as long at 10,000 2D blocks.) Tried there and not kept: a geometric nested-dissection
    ordering of the blocks (factor 88 ms, CHOLMOD's own ordering 82-90 ms) and the simplicial
    factorisation (0.9-1.0 s)."""

    def __init__(self, Eh: sp.csr_matrix, blocks: _Blocks):
        from cvxopt import cholmod, matrix, spmatrix

        n = Eh.shape[0]
        Ec = sp.csc_matrix(Eh)
        Ec.sort_indices()
        per_class, keys = [], []
        for _, _, _, _, xidx in blocks.classes:
            ng, k = xidx.shape
            cols = xidx.ravel()
            cnt = np.diff(Ec.indptr)[cols]
            src = np.repeat(Ec.indptr[cols], cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
            g = np.repeat(np.repeat(np.arange(ng), k), cnt)  # interface slot of each nonzero
            a = np.repeat(np.tile(np.arange(k), ng), cnt)  # its action within the interface
            r = Ec.indices[src]
            order = np.lexsort((r, g))
            g, a, r, v = g[order], a[order], r[order], Ec.data[src][order]
            new = np.r_[True, (g[1:] != g[:-1]) | (r[1:] != r[:-1])]
            uid = np.cumsum(new) - 1  # one id per (interface, block unknown)
            first = np.maximum.accumulate(np.where(np.r_[True, g[1:] != g[:-1]], np.arange(g.size), 0))
            local = uid - uid[first]  # its place among its interface's unknowns
            w = int(local.max(initial=-1)) + 1
            Ed = np.zeros((ng, w, k))
            Ed[g, local, a] = v
            dofs = np.full((ng, w), -1)
            dofs[g, local] = r
            ri, ci = np.repeat(dofs, w, axis=1), np.tile(dofs, (1, w))  # (ng, w*w) row and column of each entry
            keep = ((ri >= ci) & (ci >= 0)).ravel()
            key = ci.ravel()[keep].astype(np.int64) * n + ri.ravel()[keep]
            per_class.append((Ed, keep, key))
            keys.append(key)
        keys.append(np.arange(n, dtype=np.int64) * (n + 1))  # the diagonal, always in the pattern
        ukeys = np.unique(np.concatenate(keys))
        col, row = ukeys // n, ukeys % n
        self.n, self.nnz = n, ukeys.size
        # per class, the sparse map from the w x w entries of every interface to N's values
        self.classes = [(Ed, sp.csr_matrix((np.ones(key.size), (np.searchsorted(ukeys, key), np.flatnonzero(keep))),
                                           shape=(ukeys.size, keep.size))) for Ed, keep, key in per_class]
        self.diag = np.searchsorted(ukeys, np.arange(n, dtype=np.int64) * (n + 1))
        self._M = spmatrix(matrix(np.zeros(ukeys.size)), matrix(row.astype(int)), matrix(col.astype(int)), size=(n, n))
        self.F = cholmod.symbolic(self._M, uplo="L")

    def assemble(self, hinv: list[np.ndarray]) -> np.ndarray:
        """The values of N's lower triangle (in the pattern's order) for the blocks' inverses."""
        vals = np.zeros(self.nnz)
        for (Ed, to_n), Hi in zip(self.classes, hinv):
            vals += to_n @ np.matmul(np.matmul(Ed, Hi), Ed.transpose(0, 2, 1)).ravel()
        return vals

    def factor(self, hinv: list[np.ndarray], verbose: bool = False) -> None:
        """Numeric factorisation of N for the interface blocks' inverses (:meth:`_Blocks.inverse`).

        The shift starts at REG_N of the largest diagonal entry (at least 1) and rises
        1000-fold while CHOLMOD finds N numerically indefinite (pivots lost to rounding;
        the iterative refinement of each step corrects for it); ArithmeticError beyond REG_N_MAX.
        """
        from cvxopt import cholmod, matrix

        vals = self.assemble(hinv)
        diag = vals[self.diag].copy()
        scale = diag.max(initial=1.0)
        reg = REG_N
        while True:
            vals[self.diag] = diag + reg * scale
            self._M.V = matrix(vals)
            try:
                cholmod.numeric(self._M, self.F)
                return
            except ArithmeticError as exc:
                if verbose:
                    print(f"    factor failed at shift {reg:.0e}: {exc}")
                reg *= 1e3
                if reg > REG_N_MAX:
                    raise

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """N^-1 rhs for rhs (n,) or (n, k)."""
        from cvxopt import cholmod, matrix

        B = matrix(np.asfortranarray(rhs, dtype=float))
        cholmod.solve(self.F, B)
        return np.array(B).reshape(rhs.shape)


def _max_step(v: np.ndarray, dv: np.ndarray) -> float:
    """The largest step in [0, 1] that keeps v + step dv >= 0."""
    neg = dv < 0
    return min(1.0, float((-v[neg] / dv[neg]).min())) if neg.any() else 1.0


class _Newton:
    """Newton steps of one iteration, from one factorisation of N.

    Unknowns (dx, da, ds, dy, dz); right-hand sides (r1..r5) are the residuals
    of dual feasibility ``Eh.T y + Yh.T z``, the normalisation ``fL . y - 1``,
    equilibrium ``Eh x + fL a + f0``, yield ``Yh x + s`` and centring ``s z - target``.
    """

    def __init__(self, Eh, EhT, Yh, YhT, f, red, hinv, Hinv, s, z, verbose=False, q=None):
        self.Eh, self.EhT, self.Yh, self.YhT, self.f = Eh, EhT, Yh, YhT, f
        self.prox = q  # proximal weights (n_x,) or None: the x row is q dx + Eh.T dy + Yh.T dz = -r1
        self.red, self.Hinv, self.s, self.z = red, Hinv, s, z
        red.factor(hinv, verbose)
        self.nf = None  # N^-1 fL, solved with the first right-hand side
        self.fnf = 1.0

    def solve(self, r1, r2, r3, r4, r5):
        """One Newton step for the residuals r1..r5 (unrefined)."""
        Eh, EhT, Yh, f, s, z = self.Eh, self.EhT, self.Yh, self.f, self.s, self.z
        g = -r1 - self.YhT @ ((z * r4 - r5) / s)
        t = self.Hinv @ g
        if self.nf is None:  # the live-load column's solve rides with the first one
            p, self.nf = self.red.solve(np.column_stack([Eh @ t + r3, f])).T
            self.fnf = float(f @ self.nf)
        else:
            p = self.red.solve(Eh @ t + r3)
        da = (-r2 - float(f @ p)) / self.fnf
        dy = p + da * self.nf
        dx = self.Hinv @ (g - EhT @ dy)
        ds = -(Yh @ dx) - r4
        dz = (-r5 - z * ds) / s
        return [dx, da, ds, dy, dz]

    def direction(self, *rhs, refine: int = REFINE):
        """The Newton step with ``refine`` rounds of iterative refinement on the unreduced system (the
        reduction loses accuracy when D = z / s spans many orders of magnitude near the optimum)."""
        r1, r2, r3, r4, r5 = rhs
        dv = self.solve(*rhs)
        best = None
        for _ in range(refine):
            dx, da, ds, dy, dz = dv
            e0 = self.EhT @ dy + self.YhT @ dz + r1 + (0.0 if self.prox is None else self.prox * dx)
            e = (e0, float(self.f @ dy) + r2, self.Eh @ dx + self.f * da + r3,
                 self.Yh @ dx + ds + r4, self.z * ds + self.s * dz + r5)
            err = max(np.abs(np.atleast_1d(v)).max(initial=0.0) for v in e)
            if err <= REFINE_ABS or (best is not None and err >= 0.5 * best):
                break
            best = err
            dv = [v + c for v, c in zip(dv, self.solve(*e))]
        return dv


def _centrality_correctors(newton: _Newton, s: np.ndarray, z: np.ndarray, dv: list, mu_t: float,
                           k: int) -> tuple[list, float, float]:
    """Gondzio's multiple centrality correctors (Gondzio 1996, Comput. Optim. Appl. 6, 137-156;
    Colombo & Gondzio 2008, Comput. Optim. Appl. 41, 277-305) on the Mehrotra step ``dv``.

    Each corrector aims at a longer step (the current one plus MCC_DELTA): the products s z at
    that trial point outside [MCC_BETA_MIN, MCC_BETA_MAX] x mu_t (mu_t = sigma mu, the target) are
    moved back into it (those far above by at most MCC_BETA_MAX mu_t), by one more solve with
    the same factorisation and only the centring residual. A corrector is kept while it lengthens
    the step by at least MCC_GAMMA x MCC_DELTA; at most k of them. Returns the step and its
    largest primal and dual step lengths (:func:`_max_step`)."""
    ap, ad = _max_step(s, dv[2]), _max_step(z, dv[4])
    zx, zs, zy = np.zeros_like(dv[0]), np.zeros_like(dv[2]), np.zeros_like(dv[3])
    for _ in range(k):
        at, bt = min(1.0, ap + MCC_DELTA), min(1.0, ad + MCC_DELTA)
        v = (s + at * dv[2]) * (z + bt * dv[4])
        t = np.maximum(np.clip(v, MCC_BETA_MIN * mu_t, MCC_BETA_MAX * mu_t) - v, -MCC_BETA_MAX * mu_t)
        c = newton.direction(zx, 0.0, zy, zs, -t, refine=0)  # only the centring residual
        trial = [a + b for a, b in zip(dv, c)]
        ap1, ad1 = _max_step(s, trial[2]), _max_step(z, trial[4])
        if ap1 + ad1 < ap + ad + MCC_GAMMA * MCC_DELTA:
            break
        dv, ap, ad = trial, ap1, ad1
    return dv, ap, ad


class Structure:
    """What :func:`solve` builds from the matrices alone (their transposes, the interface blocks and
    N's pattern with its symbolic factorisation), kept for a series of solves with the same Eh, Yh
    and x_group (the iterative LP: 0.3 s per LP at 10,050 2D blocks)."""

    def __init__(self, Eh: sp.csr_matrix, Yh: sp.csr_matrix, x_group: np.ndarray):
        self.Eh, self.Yh = sp.csr_matrix(Eh), sp.csr_matrix(Yh)
        self.EhT, self.YhT = self.Eh.T.tocsr(), self.Yh.T.tocsr()
        self.blocks = _Blocks(self.Yh, np.asarray(x_group))
        self.red = _Reduced(self.Eh, self.blocks)


def solve(Eh: sp.csr_matrix, Yh: sp.csr_matrix, f0h: np.ndarray, fLh: np.ndarray, x_group: np.ndarray,
          tol: float = 1e-9, max_iter: int = 200, verbose: bool = False, c: np.ndarray | None = None,
          warm: dict | None = None, q: np.ndarray | None = None, x_ref: np.ndarray | None = None,
          correctors: int = MCC, structure: Structure | None = None, mu_diverged: float | None = None,
          almost: float | None = None) -> dict:
    """Static LP by the structured interior point method (see :func:`_solve`).

    BLAS runs single-threaded meanwhile: the method makes many small BLAS calls
    (dot products of the slack and multiplier vectors), and with a second thread
    each waits for a core (docs/performance.md, 'Measurements moved from code
    comments').
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _solve(Eh, Yh, f0h, fLh, x_group, tol, max_iter, verbose, c, warm, q, x_ref, correctors, structure,
                      mu_diverged, almost)


def _solve(Eh, Yh, f0h, fLh, x_group, tol, max_iter, verbose, c=None, warm=None, q=None, x_ref=None,
           correctors=MCC, structure=None, mu_diverged=None, almost=None) -> dict:
    """Static LP by the structured interior point method.

    x_group: (n_x,) interface of each action (sorted). Returns a dict with
    status ("optimal" or "failed"), alpha, xh (n_x,), vh (n_dof,), lamh
    (n_faces,), s (m,) the slacks, iterations, reason, diverged (``mu_diverged`` stopped it) and
    per-phase seconds. ``tol`` bounds the
    relative primal and dual residuals and the duality gap (scaled problem). ``c``
    (m,): right-hand side of the yield rows (default 0). ``warm``: a result of an earlier
    solve of the same matrices (keys xh, alpha, vh, s, lamh) to start from, its slacks and
    multipliers raised to :data:`WARM_SHIFT` x their mean (default: the cold start x = 0,
    s = z = 1). ``q`` (n_x,) >= 0 and ``x_ref`` (n_x,): a proximal term, the objective becomes
    ``-alpha + 1/2 sum q (x - x_ref)^2`` (a convex QP; primal and dual take one step length).
    ``correctors``: Gondzio's centrality correctors per iteration (:func:`_centrality_correctors`).
    On an LP whose optimal face is not one point they change which point of it is returned (the
    correctors centre less): the iterative LP asks for none (iterative_lp.ITERATIVE_CORRECTORS).
    ``structure``: a :class:`Structure` of these Eh, Yh and x_group, built once for many solves.
    ``mu_diverged`` (None: never): stop, failed, once the mean complementarity s.z exceeds this x
    its first value. On an infeasible LP it grows without bound (a snap's piece of 3,024 2D
    blocks: 1 to 4e6 in 9 iterations, then about 1e9 to iteration 60), where a feasible one's falls.
    ``almost`` (None: never): when the method stalls (:data:`ALMOST_STALL`) or runs out of
    iterations, its best iterate (lowest largest relative residual) is returned with status
    "almost" if that residual is at most ``almost``. Near a degenerate optimum the residuals can
    stop falling short of ``tol``: a 12-block 3D wall's iterative LP reached 3e-8 at iteration 10
    and then wandered between 1e-8 and 8e-7 for 190 iterations.
    """
    t0 = time.perf_counter()
    if structure is None:
        structure = Structure(Eh, Yh, x_group)
    elif structure.Eh.shape != Eh.shape or structure.Yh.shape != Yh.shape:
        raise ValueError("the structure was built for matrices of other shapes")
    st = structure
    Eh, Yh, EhT, YhT, blocks, red = st.Eh, st.Yh, st.EhT, st.YhT, st.blocks, st.red
    n_x, m, nd = Yh.shape[1], Yh.shape[0], Eh.shape[0]
    b = -np.asarray(f0h, float)
    f = np.asarray(fLh, float)
    x = np.zeros(n_x)
    a = 0.0
    s = np.ones(m)
    z = np.ones(m)
    y = np.zeros(nd)
    cy = np.zeros(Yh.shape[0]) if c is None else np.asarray(c, float)
    if warm is not None:
        x, a, y = warm["xh"].copy(), float(warm["alpha"]), warm["vh"].copy()
        s = np.maximum(warm["s"], WARM_SHIFT * max(float(np.mean(np.abs(warm["s"]))), 1e-300))
        z = np.maximum(warm["lamh"], WARM_SHIFT * max(float(np.mean(np.abs(warm["lamh"]))), 1e-300))
    nb = 1.0 + np.abs(b).max(initial=0.0)
    nc = 1.0 + np.abs(cy).max(initial=0.0)
    t_setup = time.perf_counter() - t0
    t_fact = 0.0
    status, reason = IpmStatus.FAILED, f"not converged in {max_iter} iterations"
    it = 0
    mu0 = None
    diverged = False
    best = {"err": np.inf, "it": 0}
    # with ``almost``, one more pass evaluates the last step's point (and takes no step)
    for it in range(1, max_iter + 1 + (almost is not None)):
        rd = EhT @ y + YhT @ z
        if q is not None:
            rd = rd + q * (x - x_ref)
        ra = float(f @ y) - 1.0
        rp = Eh @ x + f * a - b
        rs = Yh @ x + s - cy
        mu = float(s @ z) / m
        pobj, dobj = -a, float(-b @ y - cy @ z)
        gap = abs(pobj - dobj) / (1.0 + abs(pobj)) if q is None else abs(float(s @ z)) / (1.0 + abs(a))
        res_p = max(np.abs(rp).max(initial=0.0) / nb, np.abs(rs).max(initial=0.0) / nc)
        res_d = max(np.abs(rd).max(initial=0.0) / (1.0 + np.abs(z).max(initial=0.0)), abs(ra))
        if verbose:
            print(f"{it:3d} alpha {a:.10f} primal {res_p:.1e} dual {res_d:.1e} gap {gap:.1e} mu {mu:.1e}")
        if res_p <= tol and res_d <= tol and gap <= tol:
            status, reason = IpmStatus.OPTIMAL, ""
            break
        if almost is not None:
            err = max(res_p, res_d, gap)
            if err < best["err"]:
                best.update(err=err, it=it, x=x.copy(), a=a, s=s.copy(), z=z.copy(), y=y.copy())
            elif it - best["it"] >= ALMOST_STALL and best["err"] <= almost:
                reason = f"stalled: no new low of the residuals for {ALMOST_STALL} iterations"
                break
            if it > max_iter:
                break
        if not np.all(np.isfinite([a, mu, res_p, res_d])):
            reason = "the iterates are no longer finite"
            break
        mu0 = mu if mu0 is None else mu0
        if mu_diverged is not None and mu > mu_diverged * max(mu0, 1e-300):
            reason = f"mu grew from {mu0:.1e} to {mu:.1e} in {it} iterations: probably no feasible point"
            diverged = True
            break
        if abs(a) > ALPHA_DIVERGED:
            reason = f"alpha diverges ({a:.3g}): no collapse mechanism under this live load?"
            break
        tf = time.perf_counter()
        d = z / s
        if not np.all(np.isfinite(d)):
            reason = f"a slack reached zero at iteration {it}"
            break
        try:
            hinv = blocks.inverse(d, q)
            newton = _Newton(Eh, EhT, Yh, YhT, f, red, hinv, blocks.matrix(hinv), s, z, verbose, q)
        except ArithmeticError:
            reason = f"the reduced system is not positive definite at iteration {it}"
            break
        except np.linalg.LinAlgError as exc:
            reason = f"an interface block could not be inverted at iteration {it} ({exc})"
            break
        t_fact += time.perf_counter() - tf
        res = (rd, ra, rp, rs)
        dv = newton.direction(*res, s * z, refine=REFINE_PREDICTOR)  # predictor (affine scaling)
        ap, ad = _max_step(s, dv[2]), _max_step(z, dv[4])
        mu_aff = float((s + ap * dv[2]) @ (z + ad * dv[4])) / m
        sigma = (mu_aff / mu) ** 3
        dv = newton.direction(*res, s * z + dv[2] * dv[4] - sigma * mu)  # corrector
        (dx, da, ds, dy, dz), ap, ad = _centrality_correctors(newton, s, z, dv, sigma * mu, correctors)
        ap, ad = 0.99 * ap, 0.99 * ad
        if q is not None:
            ap = ad = min(ap, ad)
        if verbose:
            print(f"    steps {ap:.3f} {ad:.3f} sigma {sigma:.2e}")
        x += ap * dx
        a += ap * da
        s += ap * ds
        y += ad * dy
        z += ad * dz
    if status != IpmStatus.OPTIMAL and almost is not None and best["err"] <= almost:
        status, reason = IpmStatus.ALMOST, f"{reason}; the best iterate ({best['it']}), residual {best['err']:.1e}, returned"
        x, a, s, z, y = best["x"], best["a"], best["s"], best["z"], best["y"]
    return {"status": status, "reason": reason, "diverged": diverged, "alpha": a, "xh": x, "vh": y, "lamh": z,
            "s": s, "iterations": min(it, max_iter),
            "setup_s": t_setup, "factor_s": t_fact, "solve_s": time.perf_counter() - t0}

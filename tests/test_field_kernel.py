"""The compiled kernels of the synthesis (ocp/synthesis/_field.c) against a plain-Python
transliteration of their algorithm, bit for bit: every cell of V, N, P, B, the wide flags and the
counts, on random strips over small grids, on the circle and on the plane."""

import math

import numpy as np
import pytest

from ocp.synthesis import field


def _triangle(V, N, P, B, grid, a, b, c, ident, branch):
    x0, dx, y0, dy = grid
    nx, ny = V.shape
    xmin, xmax = min(a[0], b[0], c[0]), max(a[0], b[0], c[0])
    ymin, ymax = min(a[1], b[1], c[1]), max(a[1], b[1], c[1])
    i0, i1 = max(0, int(math.ceil((xmin - x0) / dx))), min(nx - 1, int(math.floor((xmax - x0) / dx)))
    j0, j1 = max(0, int(math.ceil((ymin - y0) / dy))), min(ny - 1, int(math.floor((ymax - y0) / dy)))
    det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1])
    if det == 0.0:
        return
    for i in range(i0, i1 + 1):
        x = x0 + i * dx
        for j in range(j0, j1 + 1):
            y = y0 + j * dy
            l1 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / det
            l2 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / det
            l3 = 1.0 - l1 - l2
            if l1 < -1e-12 or l2 < -1e-12 or l3 < -1e-12:
                continue
            s = l1 * a[2] + l2 * b[2] + l3 * c[2]
            if s < V[i, j]:
                V[i, j] = s
                N[i, j] = a[3] if (l1 >= l2 and l1 >= l3) else (b[3] if l2 >= l3 else c[3])
                P[i, j] = ident
                B[i, j] = branch


def _strip(V, N, P, B, grid, A, C, ts, ident, circle, max_cells, wide):
    x0, dx, y0, dy = grid
    x1 = x0 + dx * (V.shape[0] - 1)
    count = 0
    for j in range(len(ts) - 1):
        p, q, r, s_ = A[j], C[j], C[j + 1], A[j + 1]
        spread = max(abs(p[0] - q[0]) / dx, abs(p[1] - q[1]) / dy, abs(s_[0] - r[0]) / dx, abs(s_[1] - r[1]) / dy)
        wide[j] = spread > max_cells
        if wide[j]:
            count += 1
            continue
        lo, hi = min(p[0], q[0], r[0], s_[0]), max(p[0], q[0], r[0], s_[0])
        k0, k1 = 0, 0
        if circle:
            k0, k1 = int(math.ceil((x0 - hi) / (2 * math.pi))), int(math.floor((x1 - lo) / (2 * math.pi)))
        for k in range(k0, k1 + 1):
            sh = 2 * math.pi * k
            va, vb = [p[0] + sh, p[1], ts[j], p[2]], [q[0] + sh, q[1], ts[j], q[2]]
            vc, vd = [r[0] + sh, r[1], ts[j + 1], r[2]], [s_[0] + sh, s_[1], ts[j + 1], s_[2]]
            _triangle(V, N, P, B, grid, va, vb, vc, ident, k)
            _triangle(V, N, P, B, grid, va, vc, vd, ident, k)
    return count


def _undominated(V, grid, ra, rb, ts, wide, circle):
    x0, dx, y0, dy = grid
    nx, ny = V.shape
    x1, y1 = x0 + dx * (nx - 1), y0 + dy * (ny - 1)
    for j in range(len(wide)):
        if not wide[j]:
            continue
        rows = (ra[j], rb[j], ra[j + 1], rb[j + 1])
        xs, ys = [row[0] for row in rows], [row[1] for row in rows]
        if max(ys) >= y0 and min(ys) <= y1:
            if min(ys) < y0 or max(ys) > y1:
                return True
            lo, hi = min(xs), max(xs)
            k0, k1 = 0, 0
            if circle:
                k0, k1 = int(math.ceil((x0 - hi) / (2 * math.pi))), int(math.floor((x1 - lo) / (2 * math.pi)))
            for k in range(k0, k1 + 1):
                if lo + 2 * math.pi * k < x0 or hi + 2 * math.pi * k > x1:
                    return True
        for c, row in enumerate(rows):
            t = ts[j] if c < 2 else ts[j + 1]
            jj = int(round((row[1] - y0) / dy))
            if jj < 0 or jj >= ny:
                continue
            k0, k1 = 0, 0
            if circle:
                k0 = int(math.ceil((x0 - row[0]) / (2 * math.pi)))
                k1 = int(math.floor((x0 + dx * (nx - 1) - row[0]) / (2 * math.pi)))
            for k in range(k0, k1 + 1):
                i = int(round((row[0] + 2 * math.pi * k - x0) / dx))
                if 0 <= i < nx and not V[i, jj] < t - field.DOMINATED:
                    return True
    return False


def _same(a, b):
    return a.dtype == b.dtype and np.array_equal(np.ascontiguousarray(a).view(np.uint8), np.ascontiguousarray(b).view(np.uint8))


@pytest.mark.parametrize("circle", [True, False])
def test_the_compiled_strip_and_dominance_are_the_transliteration_bit_for_bit(circle):
    rng = np.random.default_rng(1 + circle)
    drawn = refined = 0
    verdicts = set()
    for _ in range(12):
        nx, ny = rng.integers(3, 25, 2)
        grid = np.array([rng.uniform(-4, 4), rng.uniform(0.05, 0.3), rng.uniform(-3, 3), rng.uniform(0.05, 0.3)])
        arrays = [np.full((nx, ny), np.inf), np.full((nx, ny), -1, dtype=np.int64), np.full((nx, ny, 2), np.nan),
                  np.zeros((nx, ny), dtype=np.int64)]
        mine = [a.copy() for a in arrays]
        for _ in range(4):
            m = int(rng.integers(3, 20))
            ts = np.linspace(0.0, rng.uniform(1, 8), m)
            # a strip across the grid (shifted by 2 pi k on the circle), a few cells wide or much wider
            theta = np.linspace(grid[0], grid[0] + grid[1] * nx, m) + 2 * math.pi * circle * rng.integers(-1, 2)
            omega = grid[2] + grid[3] * ny * rng.uniform(0.2, 0.8) + rng.normal(scale=grid[3], size=m)
            A = np.column_stack([theta, omega, rng.integers(0, 4, m).astype(float)])
            C = A.copy()
            C[:, 1] += grid[3] * rng.choice([1.0, 2.5, 8.0]) + rng.normal(scale=grid[3] / 2, size=m)
            ident, max_cells = rng.uniform(0, 6, 2), float(rng.choice([1.0, 3.0]))
            wide, wide_mine = np.zeros(m - 1, dtype=np.bool_), np.zeros(m - 1, dtype=np.bool_)
            count = field._strip(*arrays, grid, A, C, ts, ident, circle, max_cells, wide)
            assert count == _strip(*mine, grid, A, C, ts, ident, circle, max_cells, wide_mine)
            assert all(_same(a, b) for a, b in zip(arrays, mine)) and _same(wide, wide_mine)
            for flags in (wide, rng.random(m - 1) < 0.5):
                verdict = field._undominated(arrays[0], grid, A, C, ts, flags, circle)
                assert verdict == _undominated(mine[0], grid, A, C, ts, flags, circle)
                verdicts.add(verdict)
            drawn += int(np.isfinite(arrays[0]).sum())
            refined += count
    assert drawn > 500 and refined > 20 and verdicts == {True, False}       # every branch exercised


@pytest.mark.parametrize("circle", [True, False])
def test_the_compiled_dominance_of_strips_inside_the_grid_is_the_transliteration(circle):
    """Wide quadrilaterals inside the grid: the verdict is the values drawn at their corners."""
    rng = np.random.default_rng(3 + circle)
    verdicts = []
    for _ in range(200):
        nx, ny = rng.integers(5, 30, 2)
        grid = np.array([rng.uniform(-3, 0), rng.uniform(0.05, 0.2), rng.uniform(-3, 3), rng.uniform(0.05, 0.2)])
        m = int(rng.integers(2, 8))
        ts = np.sort(rng.uniform(0, 5, m))
        inside = lambda: np.column_stack([grid[0] + grid[1] * rng.uniform(1, nx - 2, m),
                                          grid[2] + grid[3] * rng.uniform(1, ny - 2, m), np.zeros(m)])
        ra, rb = inside(), inside()
        V = rng.uniform(0, 5, (nx, ny))
        V[rng.random((nx, ny)) < 0.2] = np.inf
        flags = rng.random(m - 1) < 0.3
        verdict = field._undominated(V, grid, ra, rb, ts, flags, circle)
        assert verdict == _undominated(V, grid, ra, rb, ts, flags, circle)
        verdicts.append(verdict)
    assert 20 < sum(verdicts) < 180

/* Point probes (MPS-weighted averages of pressure and velocity at arbitrary
 * points) and the surge front. Probes sort the particles into their own cell
 * grid of the density radius: the solver's neighbour grid was built from
 * positions the particles have since left (by up to more than half the
 * skin after the correction stage), and a const solver cannot rebuild it. */
#include "core/core.h"
#include "solver/solver.h"

#include <math.h>
#include <stdlib.h>

/* Keeps the grid small when a few particles are far apart. */
#define MIN_CELL_BUDGET 65536
#define CELLS_PER_PARTICLE 4
/* Distances below this (in l0) count as this: a point on a particle takes,
 * to rounding, that particle's values instead of dividing by zero. */
#define COINCIDENT 1e-9

typedef struct probe_grid {
    double origin[2], cell;
    size_t cells[2];
    size_t *start;    /* cells + 1 */
    size_t *particle; /* fluid in the run and walls, by cell */
} probe_grid;

static size_t clamp_cell(double x, double origin, double size, size_t cells)
{
    double c = floor((x - origin) / size);
    if (!(c >= 0.0))
        return 0;
    return c >= (double)cells ? cells - 1 : (size_t)c;
}

static int grid_build(probe_grid *g, const mps2p_solver *s, double re)
{
    const double *r = s->state.position;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    size_t m = 0;
    for (size_t i = 0; i < s->count; i++) {
        if (!kind_carries_pressure(s->kind[i]))
            continue;
        m++;
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], r[2 * i + d]);
            hi[d] = fmax(hi[d], r[2 * i + d]);
        }
    }
    if (m == 0) { /* cannot happen for a solver with fluid, but keep the grid valid */
        lo[0] = lo[1] = hi[0] = hi[1] = 0.0;
    }
    double width = hi[0] - lo[0], height = hi[1] - lo[1];
    double budget = fmax((double)MIN_CELL_BUDGET, (double)CELLS_PER_PARTICLE * (double)m);
    double cell = re;
    if ((width / cell + 1.0) * (height / cell + 1.0) > budget) /* as in neighbours.c */
        cell = fmax(sqrt(width * height / budget), fmax(width, height) / budget) * 1.01 + re;
    g->origin[0] = lo[0];
    g->origin[1] = lo[1];
    g->cell = cell;
    g->cells[0] = (size_t)(width / cell) + 1;
    g->cells[1] = (size_t)(height / cell) + 1;
    size_t cells = g->cells[0] * g->cells[1];
    g->start = calloc(cells + 1, sizeof *g->start);
    g->particle = malloc((m ? m : 1) * sizeof *g->particle);
    size_t *cursor = malloc(cells * sizeof *cursor);
    if (!g->start || !g->particle || !cursor) {
        free(cursor);
        return MPS2P_ERR_NOMEM;
    }
    /* counting sort, particles in index order inside each cell */
    for (size_t i = 0; i < s->count; i++) {
        if (!kind_carries_pressure(s->kind[i]))
            continue;
        size_t cx = clamp_cell(r[2 * i], g->origin[0], cell, g->cells[0]);
        size_t cy = clamp_cell(r[2 * i + 1], g->origin[1], cell, g->cells[1]);
        g->start[cy * g->cells[0] + cx + 1]++;
    }
    for (size_t c = 0; c < cells; c++)
        g->start[c + 1] += g->start[c];
    for (size_t c = 0; c < cells; c++)
        cursor[c] = g->start[c];
    for (size_t i = 0; i < s->count; i++) {
        if (!kind_carries_pressure(s->kind[i]))
            continue;
        size_t cx = clamp_cell(r[2 * i], g->origin[0], cell, g->cells[0]);
        size_t cy = clamp_cell(r[2 * i + 1], g->origin[1], cell, g->cells[1]);
        g->particle[cursor[cy * g->cells[0] + cx]++] = i;
    }
    free(cursor);
    return MPS2P_OK;
}

/* Weighted sums around one point over the 3x3 cells (cell >= re). */
typedef struct probe_sums {
    double all, pressure, fluid, velocity[2];
} probe_sums;

static probe_sums sample(const probe_grid *g, const mps2p_solver *s, double re,
                         const double point[2])
{
    probe_sums sums = {0.0, 0.0, 0.0, {0.0, 0.0}};
    const double *r = s->state.position;
    const double closest = COINCIDENT * s->l0;
    long cx = (long)clamp_cell(point[0], g->origin[0], g->cell, g->cells[0]);
    long cy = (long)clamp_cell(point[1], g->origin[1], g->cell, g->cells[1]);
    for (long y = cy - 1; y <= cy + 1; y++) {
        if (y < 0 || y >= (long)g->cells[1])
            continue;
        for (long x = cx - 1; x <= cx + 1; x++) {
            if (x < 0 || x >= (long)g->cells[0])
                continue;
            size_t cell = (size_t)y * g->cells[0] + (size_t)x;
            for (size_t k = g->start[cell]; k < g->start[cell + 1]; k++) {
                size_t j = g->particle[k];
                double distance = hypot(r[2 * j] - point[0], r[2 * j + 1] - point[1]);
                if (distance >= re)
                    continue;
                double w = re / fmax(distance, closest) - 1.0;
                sums.all += w;
                sums.pressure += w * s->state.pressure[j];
                if (s->kind[j] == MPS2P_KIND_FLUID) {
                    sums.fluid += w;
                    sums.velocity[0] += w * s->state.velocity[2 * j];
                    sums.velocity[1] += w * s->state.velocity[2 * j + 1];
                }
            }
        }
    }
    return sums;
}

int mps2p_solver_probe(const mps2p_solver *s, size_t count, const double *points,
                       double *pressure, double *velocity, int *inside)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_probe: solver is NULL");
    if (count == 0)
        return MPS2P_OK;
    if (!points || !pressure)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_probe: %s is NULL",
                    !points ? "points" : "pressure output");
    for (size_t k = 0; k < count; k++)
        if (!isfinite(points[2 * k]) || !isfinite(points[2 * k + 1]))
            return fail(NULL, MPS2P_ERR_INVALID, "probe point %zu is not finite: (%g, %g)", k,
                        points[2 * k], points[2 * k + 1]);
    const double re = s->params.re_density * s->l0;
    const double threshold = 0.5 * s->params.beta * s->n0_density;
    probe_grid grid = {{0.0, 0.0}, 0.0, {0, 0}, NULL, NULL};
    int status = grid_build(&grid, s, re);
    if (status != MPS2P_OK) {
        free(grid.start);
        free(grid.particle);
        return fail(NULL, status, "out of memory probing %zu particles", s->count);
    }
    for (size_t k = 0; k < count; k++) {
        probe_sums sums = sample(&grid, s, re, &points[2 * k]);
        int in = sums.fluid >= threshold && sums.fluid > 0.0;
        pressure[k] = in ? sums.pressure / sums.all : 0.0;
        if (velocity) {
            velocity[2 * k] = in ? sums.velocity[0] / sums.fluid : 0.0;
            velocity[2 * k + 1] = in ? sums.velocity[1] / sums.fluid : 0.0;
        }
        if (inside)
            inside[k] = in;
    }
    free(grid.start);
    free(grid.particle);
    return MPS2P_OK;
}

int mps2p_solver_front(const mps2p_solver *s, int fluid_id, double below_y, double *front_x)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_front: solver is NULL");
    if (!front_x)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_front: front_x output pointer is NULL");
    if (fluid_id < -1 || fluid_id >= s->fluid_count)
        return fail(NULL, MPS2P_ERR_INVALID,
                    "mps2p_solver_front: no fluid with id %d (the solver has %d; -1 = any)",
                    fluid_id, s->fluid_count);
    if (isnan(below_y))
        return fail(NULL, MPS2P_ERR_INVALID, "mps2p_solver_front: below_y is NaN");
    double largest = -INFINITY;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID || (fluid_id >= 0 && s->fluid_id[i] != fluid_id))
            continue;
        if (s->state.position[2 * i + 1] < below_y)
            largest = fmax(largest, s->state.position[2 * i]);
    }
    if (largest == -INFINITY && fluid_id < 0)
        return fail(NULL, MPS2P_ERR_INVALID,
                    "mps2p_solver_front: no fluid particle below y = %g", below_y);
    if (largest == -INFINITY)
        return fail(NULL, MPS2P_ERR_INVALID,
                    "mps2p_solver_front: no particle of fluid %d (\"%s\") below y = %g",
                    fluid_id, s->fluids[fluid_id].name, below_y);
    *front_x = largest + 0.5 * s->l0;
    return MPS2P_OK;
}

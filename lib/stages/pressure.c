/* Pressure Poisson equation: assemble the sparse system and solve it.
 *   -<lap p>_i + (rho_i kappa / dt^2) p_i = source_i (see source_term)
 * over fluid and wall particles that are not free surface, and free-surface
 * fluid particles with surface_pressure extrapolated (extrapolate_surface);
 * other free-surface particles are Dirichlet (p = 0), dummy walls and
 * particles out of the run (MPS2P_KIND_OUT) carry no pressure. The
 * compressibility term kappa keeps the matrix positive definite even for a
 * fluid cluster that touches no free surface. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Room for entries (column and value) in arrays holding capacity, a
 * sixteenth to spare: the pattern grows by a few entries a step at most, and
 * the matrix is the solver's second-largest array. 0 when out of memory (the
 * arrays and capacity stay valid). */
static int grow_entries(int **column, double **value, size_t *capacity, size_t entries)
{
    if (entries <= *capacity)
        return 1;
    size_t grown_capacity = entries + entries / 16 + 16;
    int *grown_column = realloc(*column, grown_capacity * sizeof *grown_column);
    if (grown_column)
        *column = grown_column;
    double *grown_value = realloc(*value, grown_capacity * sizeof *grown_value);
    if (grown_value)
        *value = grown_value;
    if (!grown_column || !grown_value)
        return 0;
    *capacity = grown_capacity;
    return 1;
}

static int grow_matrix(sparse_matrix *m, int rows, size_t entries)
{
    if ((size_t)rows + 1 > m->row_capacity) {
        int *grown = realloc(m->row_start, ((size_t)rows + 1) * sizeof *grown);
        if (!grown)
            return MPS2P_ERR_NOMEM;
        m->row_start = grown;
        m->row_capacity = (size_t)rows + 1;
    }
    return grow_entries(&m->column, &m->value, &m->capacity, entries) ? MPS2P_OK
                                                                       : MPS2P_ERR_NOMEM;
}

/* Participants: the system's mask when it has one, else the fluid in the
 * run and the walls. */
static int takes_part(const mps2p_solver *s, const ppe_system *sys, size_t j)
{
    return sys->part ? sys->part[j] != 0 : kind_carries_pressure(s->kind[j]);
}

/* The PPE source, rho/dt^2 times a number-density deviation over n0:
 *   density  gamma (n* - n0): Koshizuka and Oka, the whole deviation relaxed;
 *   mixed    a (n* - n^k) + gamma (n^k - n0): this step's change (the
 *            velocity divergence, measured with the number density itself)
 *            times a (the system's step_gain), the drift accumulated before it
 *            relaxed (after Tanaka and Masunaga 2010);
 *   ecs      a (n* - n^k) + |e| (n^k - n0), e = (n^k - n0)/n0: as mixed, with
 *            the drift's factor the error itself, after Khayyer and Gotoh's
 *            error-compensating source (a simplified form, not theirs
 *            exactly): noise-sized errors are hardly amplified by 1/dt^2.
 * The step's change in full (a = 1) over-answers it: still water's first
 * step overshoots 2.4 times and rings, and a flow's pressure scatters from
 * step to step; a = 0.4 (the default scheme's ppe_step_gain) takes a quarter
 * off a turning stream's wall-pressure scatter, its mean unchanged, and two
 * fifths off Buchner's probe noise (docs/validation.md). */
static double source_term(const mps2p_solver *s, const ppe_system *sys, size_t i, double dt)
{
    const double n0 = s->n0_density, gamma = s->params.ppe_relaxation;
    const double gain = sys->step_gain;
    const double scale = sys->density[i] / (dt * dt) / n0;
    const double n_star = sys->n_star[i];
    if (s->params.ppe_source == PPE_SOURCE_DENSITY || sys->density_source)
        return scale * gamma * (n_star - n0);
    const double n_start = sys->n_start[i]; /* allocated for these sources only */
    if (s->params.ppe_source == PPE_SOURCE_MIXED)
        return scale * (gain * (n_star - n_start) + gamma * (n_start - n0));
    return scale * (gain * (n_star - n_start) + fabs(n_start - n0) / n0 * (n_start - n0));
}

/* The stage workspace: every stage fills it before reading it, and only the
 * assembly reads the surface's diagonal. */
double *surface_diagonal_of(mps2p_solver *s)
{
    return s->params.surface_pressure == SURFACE_PRESSURE_EXTRAPOLATED ? s->scratch : NULL;
}

/* The single-phase system: every fluid and wall particle, its own density. */
static ppe_system single_phase_system(mps2p_solver *s)
{
    ppe_system sys = {.surface = s->on_surface,
                      .n_star = s->number_density,
                      .n_start = s->number_density_start,
                      .density = s->density,
                      .pressure = s->state.pressure,
                      .hydrostatic_ghosts = s->params.wall_ghosts == WALL_GHOSTS_HYDROSTATIC,
                      .step_gain = s->params.ppe_step_gain,
                      .surface_diagonal = surface_diagonal_of(s),
                      .unknowns = s->ppe_unknowns};
    return sys;
}

int pressure_assemble(mps2p_solver *s, double dt)
{
    ppe_system sys = single_phase_system(s);
    int status = pressure_assemble_system(s, dt, &sys);
    s->ppe_unknowns = sys.unknowns;
    s->ppe_iterations = 0;
    s->ppe_residual = 0.0;
    return status;
}

int pressure_solve(mps2p_solver *s, double dt)
{
    (void)dt;
    ppe_system sys = single_phase_system(s);
    int status = pressure_solve_system(s, &sys);
    s->ppe_iterations = sys.iterations;
    s->ppe_iterations_total += sys.iterations;
    s->ppe_residual = sys.residual;
    return status;
}

/* Row i (unknown number row) of the system, its entries from m->column +
 * first on, in neighbour order with the diagonal in its sorted place; the
 * right-hand side and CG's warm start too. Returns the end of the row.
 * Entries: the diagonal and the unknown neighbours within re (every one in
 * the list with ppe_pattern neighbour_list, zero beyond re).
 * Hydrostatic ghosts (option wall_ghosts; the systems of the water): a
 * dummy, or a wall on the free surface (a dry wall), seen from row i takes
 * p_i + rho_i g . r_ij, so its Laplacian term w (p_j - p_i) is the known
 * w rho_i g . r_ij: it goes to the right-hand side and the matrix stays
 * symmetric. Koshizuka and Oka's dummies are left out of the Laplacian, and
 * a dry wall is p = 0: both bend the hydrostatic field near walls, which
 * still water measures (docs/validation.md). */
static size_t fill_row(mps2p_solver *s, const ppe_system *sys, double dt, size_t i, int row,
                       int *column, double *value, size_t first)
{
    const double re = s->params.re_laplacian * s->l0;
    const double c = 2.0 * 2 / (s->lambda * s->n0_laplacian);
    const int whole_list = s->params.ppe_pattern == PPE_PATTERN_NEIGHBOUR_LIST;
    const int ghosts = sys->hydrostatic_ghosts;
    double g[2];
    gravity_acting(s, g);
    const double gx = g[0], gy = g[1];
    const neighbour_list *nl = &s->neighbours;
    const double *position = s->state.position;
    size_t next = first;
    long diagonal_at = -1;
    double ghost_sum = 0.0;
    double diagonal = sys->density[i] * s->params.compressibility / (dt * dt);
    for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
        size_t j = nl->index[k];
        const int ghost = ghosts && is_hydrostatic_ghost(s, sys->surface, j);
        if (!ghost && !takes_part(s, sys, j))
            continue;
        double dx = position[2 * j] - position[2 * i];
        double dy = position[2 * j + 1] - position[2 * i + 1];
        int in_range = dx * dx + dy * dy < re * re;
        if (ghost) {
            if (in_range)
                ghost_sum += c * kernel_weight(sqrt(dx * dx + dy * dy), re) *
                             sys->density[i] * (gx * dx + gy * dy);
            continue;
        }
        if (!in_range && !(whole_list && s->unknown_of[j] >= 0))
            continue;
        double w = in_range ? kernel_weight(sqrt(dx * dx + dy * dy), re) : 0.0;
        diagonal += c * w;
        if (s->unknown_of[j] < 0)
            continue;
        if (diagonal_at < 0 && j > i)
            diagonal_at = (long)next++; /* keep columns sorted */
        column[next] = (int)s->unknown_of[j];
        value[next] = -c * w;
        next++;
    }
    if (diagonal_at < 0)
        diagonal_at = (long)next++;
    /* a free-surface particle's row: the Laplacian with its missing
     * neighbours as the linear extrapolation to p = 0 half a spacing out,
     * and no source (its number density is short by those neighbours) */
    const int at_surface = sys->surface[i] && sys->surface_diagonal;
    if (at_surface)
        diagonal += sys->surface_diagonal[i];
    column[diagonal_at] = row;
    value[diagonal_at] = diagonal;
    s->rhs[row] = at_surface ? 0.0 : source_term(s, sys, i, dt);
    if (ghosts)
        s->rhs[row] += ghost_sum;
    s->solution[row] = sys->pressure[i]; /* warm start for CG */
    return next;
}

/* When the runs' room passes the int index range or the memory at hand:
 * the rows' lengths counted, then each row filled into its own slots. */
static int assemble_in_two_passes(mps2p_solver *s, const ppe_system *sys, double dt);

/* Runs whose bookkeeping an assembly keeps on the stack. */
#define STACK_RUNS 8

/* Where a run of rows is filled: its entries and their room. */
typedef struct row_run {
    int *column;
    double *value;
    size_t capacity, entries;
} row_run;

/* The rows of particles [first, end), each filled where the last one ended,
 * room made from the bound of its neighbour list (about 1.3 times its
 * entries): no counting pass. row_start gets the offsets within the run. */
static int fill_run(mps2p_solver *s, const ppe_system *sys, double dt, size_t first,
                    size_t end, row_run *run)
{
    const neighbour_list *nl = &s->neighbours;
    sparse_matrix *m = &s->matrix;
    size_t next = 0;
    for (size_t i = first; i < end; i++) {
        int row = s->unknown_of[i];
        if (row < 0)
            continue;
        size_t bound = next + (nl->start[i + 1] - nl->start[i]) + 1;
        if (bound > (size_t)INT_MAX || !grow_entries(&run->column, &run->value, &run->capacity, bound))
            return MPS2P_ERR_NOMEM;
        m->row_start[row] = (int)next;
        next = fill_row(s, sys, dt, i, row, run->column, run->value, next);
    }
    run->entries = next;
    return MPS2P_OK;
}

/* Each thread fills a contiguous run of rows in one pass, the first straight
 * into the matrix, the others into room of their own, copied in behind it
 * once every run's length is known (as the neighbour list's runs). Every
 * row is filled by one thread as with one: the same matrix for any team. */
static int assemble_in_runs(mps2p_solver *s, const ppe_system *sys, double dt)
{
    sparse_matrix *m = &s->matrix;
    const size_t n = s->count;
    /* a small system (the liquid's beside a large gas, about 450 rows in the
     * paper's case) in one run: its rows are too few to share */
    const size_t runs = m->rows < REDUCTION_BLOCK ? 1 : (size_t)team_size(s->params.threads);
    row_run stack_runs[STACK_RUNS];
    size_t stack_offsets[STACK_RUNS];
    int stack_first_rows[STACK_RUNS + 1];
    row_run *run = runs <= STACK_RUNS ? stack_runs : calloc(runs, sizeof *run);
    size_t *offset = runs <= STACK_RUNS ? stack_offsets : calloc(runs, sizeof *offset);
    int *first_row = runs <= STACK_RUNS ? stack_first_rows : calloc(runs + 1, sizeof *first_row);
    size_t stack_splits[STACK_RUNS + 1];
    size_t *split = runs <= STACK_RUNS ? stack_splits : calloc(runs + 1, sizeof *split);
    int failed = !run || !offset || !first_row || !split;
    if (!failed) {
        /* runs of about equal work, a row's work its neighbour row's length
         * (the unknowns are numbered in particle order; a scene's phases and
         * walls lie in blocks of it, with rows of different lengths) */
        const size_t *row = s->neighbours.start;
        size_t work = 0, done = 0, r = 0;
        for (size_t i = 0; i < n; i++)
            if (s->unknown_of[i] >= 0)
                work += row[i + 1] - row[i] + 1;
        for (size_t i = 0; i < n && r < runs; i++) {
            if (s->unknown_of[i] < 0)
                continue;
            while (r < runs && done >= work / runs * r + work % runs * r / runs) {
                split[r] = i;
                first_row[r] = s->unknown_of[i];
                r++;
            }
            done += row[i + 1] - row[i] + 1;
        }
        for (; r <= runs; r++) {
            split[r] = n;
            first_row[r] = m->rows;
        }
        split[0] = 0;
        run[0] = (row_run){m->column, m->value, m->capacity, 0};
        for (size_t r = 1; r < runs; r++)
            run[r] = (row_run){NULL, NULL, 0, 0};
        PARALLEL_FOR(s->params.threads, schedule(static, 1) reduction(| : failed) if (runs > 1),
        for (size_t r = 0; r < runs; r++) {
            failed |= fill_run(s, sys, dt, split[r], split[r + 1], &run[r]) != MPS2P_OK;
        });
        /* the first run's room is the matrix's, perhaps moved */
        m->column = run[0].column;
        m->value = run[0].value;
        m->capacity = run[0].capacity;
    }
    size_t total = 0;
    if (!failed) {
        for (size_t r = 0; r < runs; r++) {
            offset[r] = total;
            total += run[r].entries;
        }
        failed = total > (size_t)INT_MAX || grow_matrix(m, m->rows, total) != MPS2P_OK;
    }
    if (!failed) {
        PARALLEL_FOR(s->params.threads, schedule(static, 1) if (runs > 2),
        for (size_t r = 1; r < runs; r++) {
            if (run[r].entries > 0) {
                memcpy(m->column + offset[r], run[r].column, run[r].entries * sizeof(int));
                memcpy(m->value + offset[r], run[r].value, run[r].entries * sizeof(double));
            }
            for (int row = first_row[r]; row < first_row[r + 1]; row++)
                m->row_start[row] += (int)offset[r];
        });
        m->row_start[m->rows] = (int)total;
    }
    for (size_t r = 1; r < runs && run; r++) {
        free(run[r].column);
        free(run[r].value);
    }
    if (run != stack_runs)
        free(run);
    if (offset != stack_offsets)
        free(offset);
    if (first_row != stack_first_rows)
        free(first_row);
    if (split != stack_splits)
        free(split);
    /* the two passes decide from the exact count, and report it */
    return failed ? assemble_in_two_passes(s, sys, dt) : MPS2P_OK;
}

/* The rows' lengths counted, a row per thread at a time, then each row
 * filled into its own slots. */
static int assemble_in_two_passes(mps2p_solver *s, const ppe_system *sys, double dt)
{
    const double re = s->params.re_laplacian * s->l0;
    const int whole_list = s->params.ppe_pattern == PPE_PATTERN_NEIGHBOUR_LIST;
    const neighbour_list *nl = &s->neighbours;
    const double *position = s->state.position;
    sparse_matrix *m = &s->matrix;
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
    for (size_t i = 0; i < s->count; i++) {
        if (s->unknown_of[i] < 0)
            continue;
        size_t row_entries = 1;
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            if (s->unknown_of[j] < 0)
                continue;
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            row_entries += whole_list || dx * dx + dy * dy < re * re;
        }
        /* a row holds at most the whole list's entries, so an int once the
         * total is checked below; clamped until then */
        m->row_start[s->unknown_of[i] + 1] = row_entries > (size_t)INT_MAX ? INT_MAX
                                                                           : (int)row_entries;
    });
    size_t entries = 0;
    m->row_start[0] = 0;
    for (int row = 0; row < m->rows; row++) {
        entries += (size_t)m->row_start[row + 1];
        m->row_start[row + 1] = entries > (size_t)INT_MAX ? INT_MAX : (int)entries;
    }
    if (entries > (size_t)INT_MAX)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "pressure matrix with %zu entries is beyond the int index range", entries);
    if (grow_matrix(m, m->rows, entries) != MPS2P_OK)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "out of memory for the pressure matrix (%zu entries)", entries);
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
    for (size_t i = 0; i < s->count; i++) {
        int row = s->unknown_of[i];
        if (row >= 0)
            fill_row(s, sys, dt, i, row, m->column, m->value, (size_t)m->row_start[row]);
    });
    return MPS2P_OK;
}

/* surface_pressure = extrapolated: a free-surface fluid particle i becomes
 * an unknown whose missing neighbours (the air's side of a full lattice)
 * stand as the linear extrapolation of p_i to 0 at delta = l0/2 beyond it
 * along the outward normal, where the water's top lies (its volume l0^2 per
 * particle). A missing neighbour at depth d along the normal then adds
 * w (p_i (1 - d/delta) - p_i) = -w d p_i / delta, in all -|m_i| p_i / delta
 * with m_i = sum_j w_ij r_ij over the neighbours present (on a full lattice
 * the first moment is zero, so the missing part's is -m_i): an extra
 * diagonal c |m_i| / delta, exact for a hydrostatic field. Centre-held p = 0
 * puts the surface l0/2 too low: the pressure of a depth h - l0/2, and a
 * stream turning up a wall loses a third of its force (docs/validation.md).
 * A wall, or a particle whose moment is nil against its neighbours' weight
 * (none within re_laplacian, or a symmetric neighbourhood to rounding),
 * keeps p = 0: its row would have nothing to hold it. */
static void extrapolate_surface(const mps2p_solver *s, ppe_system *sys)
{
    const double re = s->params.re_laplacian * s->l0;
    const double c = 2.0 * 2 / (s->lambda * s->n0_laplacian);
    const double delta = 0.5 * s->l0;
    const neighbour_list *nl = &s->neighbours;
    const double *position = s->state.position;
    double *extra = sys->surface_diagonal;
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
    for (size_t i = 0; i < s->count; i++) {
        extra[i] = 0.0;
        if (!sys->surface[i] || s->kind[i] != MPS2P_KIND_FLUID || !takes_part(s, sys, i))
            continue;
        double mx = 0.0, my = 0.0, weight = 0.0;
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            /* the system's own particles and the dummies: in two phases the
             * gas is the missing side too */
            if (!takes_part(s, sys, j) && s->kind[j] != MPS2P_KIND_DUMMY)
                continue;
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            double r2 = dx * dx + dy * dy;
            if (r2 >= re * re)
                continue;
            double w = kernel_weight(sqrt(r2), re);
            mx += w * dx;
            my += w * dy;
            weight += w;
        }
        double moment = hypot(mx, my);
        extra[i] = moment > 1e-9 * weight * delta ? c * moment / delta : 0.0;
    });
}

int pressure_assemble_system(mps2p_solver *s, double dt, ppe_system *sys)
{
    /* A window's step shorter than half the chosen dt gets the pressure of a
     * step of half the chosen dt: the source (and the compressibility term)
     * scale with 1/dt^2, and a tiny step would otherwise press the whole
     * density error out in no time, with a pressure 1/dt^2 too large. */
    dt = fmax(dt, s->ppe_min_dt);

    if (sys->surface_diagonal)
        extrapolate_surface(s, sys);

    /* Number the unknowns in particle order. */
    long unknowns = 0;
    for (size_t i = 0; i < s->count; i++) {
        int known = sys->surface[i] && !(sys->surface_diagonal && sys->surface_diagonal[i] > 0.0);
        s->unknown_of[i] = (takes_part(s, sys, i) && !known) ? (int)unknowns++ : -1;
    }
    sys->unknowns = (size_t)unknowns;
    sys->iterations = 0;
    sys->residual = 0.0;
    if (unknowns == 0)
        return MPS2P_OK;

    if (unknowns >= INT_MAX)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "pressure matrix with %ld rows is beyond the int index range", unknowns);
    if (grow_matrix(&s->matrix, (int)unknowns, 0) != MPS2P_OK)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "out of memory for the pressure matrix (%ld rows)", unknowns);
    s->matrix.rows = (int)unknowns;
    return assemble_in_runs(s, sys, dt);
}

int pressure_solve_system(mps2p_solver *s, ppe_system *sys)
{
    double *pressure = sys->pressure;
    if (sys->unknowns == 0) {
        memset(pressure, 0, s->count * sizeof *pressure);
        return MPS2P_OK;
    }
    const sparse_matrix *m = &s->matrix;
    const size_t unknowns = sys->unknowns;
    size_t max_iterations = s->params.cg_max_iterations > 0.0
                                ? (size_t)s->params.cg_max_iterations
                                : 10 * unknowns + 100;
    /* a density, gravity or step at the ends of a double's range makes the
     * source overflow (rho / dt^2), or its square in CG's norms: say so, not
     * "residual nan" */
    double square_sum = 0.0;
    for (size_t u = 0; u < unknowns; u++)
        square_sum += s->rhs[u] * s->rhs[u];
    if (!isfinite(square_sum)) {
        size_t i = 0;
        double largest = 0.0;
        for (size_t k = 0; k < s->count; k++)
            if (s->unknown_of[k] >= 0 && !(fabs(s->rhs[s->unknown_of[k]]) <= largest)) {
                largest = fabs(s->rhs[s->unknown_of[k]]);
                i = k;
            }
        return fail(s->error, MPS2P_ERR_SOLVE,
                    "step %llu at t = %.6g s: the pressure equation's source is %g at particle "
                    "%zu (its density %g kg/m^3), too large to solve: a density, gravity or "
                    "time step beyond what the solver can compute with",
                    (unsigned long long)s->steps + 1, s->time, largest, i, sys->density[i]);
    }
    char message[ERROR_MESSAGE_SIZE];
    size_t iterations = 0;
    double residual = 0.0;
    double tolerance = sys->tolerance > 0.0 ? sys->tolerance : s->params.cg_tolerance;
    int status = linear_solver_solve(s->linear, m, s->rhs, s->solution, tolerance,
                                     max_iterations, &iterations, &residual, message,
                                     sizeof message);
    sys->iterations = iterations;
    sys->residual = residual;
    if (status != MPS2P_OK)
        return fail(s->error, status, "step %llu at t = %.6g s: pressure solve failed: %s",
                    (unsigned long long)s->steps + 1, s->time, message);

    int clamp = s->params.clamp_negative_pressure != 0.0 && !sys->keep_negative;
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        double p = s->unknown_of[i] >= 0 ? s->solution[s->unknown_of[i]] : 0.0;
        pressure[i] = (clamp && p < 0.0) ? 0.0 : p;
    });
    return MPS2P_OK;
}

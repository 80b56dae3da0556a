/* Pressure Poisson equation: assemble the sparse system and solve it.
 *   -<lap p>_i + (rho_i kappa / dt^2) p_i = source_i (see source_term)
 * over fluid and wall particles that are not free surface. Free-surface
 * particles are Dirichlet (p = 0), dummy walls carry no pressure. The
 * compressibility term kappa keeps the matrix positive definite even for a
 * fluid cluster that touches no free surface. */
#include "internal.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int grow_matrix(sparse_matrix *m, int rows, size_t entries)
{
    if ((size_t)rows + 1 > m->row_capacity) {
        int *grown = realloc(m->row_start, ((size_t)rows + 1) * sizeof *grown);
        if (!grown)
            return MPS2P_ERR_NOMEM;
        m->row_start = grown;
        m->row_capacity = (size_t)rows + 1;
    }
    if (entries > m->capacity) {
        size_t capacity = entries + entries / 4 + 16;
        int *column = realloc(m->column, capacity * sizeof *column);
        if (column)
            m->column = column;
        double *value = realloc(m->value, capacity * sizeof *value);
        if (value)
            m->value = value;
        if (!column || !value)
            return MPS2P_ERR_NOMEM;
        m->capacity = capacity;
    }
    return MPS2P_OK;
}

static int takes_part(const mps2p_solver *s, size_t j)
{
    return s->kind[j] != MPS2P_KIND_DUMMY;
}

/* The PPE source, rho/dt^2 times a number-density deviation over n0:
 *   density  gamma (n* - n0): Koshizuka and Oka, the whole deviation relaxed;
 *   mixed    (n* - n^k) + gamma (n^k - n0): this step's change (the velocity
 *            divergence, measured with the number density itself) in full,
 *            the drift accumulated before it relaxed (after Tanaka and
 *            Masunaga 2010);
 *   ecs      (n* - n^k) + |e| (n^k - n0), e = (n^k - n0)/n0: as mixed, with
 *            the drift's factor the error itself, after Khayyer and Gotoh's
 *            error-compensating source (a simplified form, not theirs
 *            exactly): noise-sized errors are hardly amplified by 1/dt^2. */
static double source_term(const mps2p_solver *s, size_t i, double dt)
{
    const double n0 = s->n0_density, gamma = s->params.ppe_relaxation;
    const double scale = s->density[i] / (dt * dt) / n0;
    const double n_star = s->number_density[i];
    if (s->params.ppe_source == PPE_SOURCE_DENSITY)
        return scale * gamma * (n_star - n0);
    const double n_start = s->number_density_start[i]; /* allocated for these sources only */
    if (s->params.ppe_source == PPE_SOURCE_MIXED)
        return scale * ((n_star - n_start) + gamma * (n_start - n0));
    return scale * ((n_star - n_start) + fabs(n_start - n0) / n0 * (n_start - n0));
}

int pressure_assemble(mps2p_solver *s, double dt)
{
    const double re = s->params.re_laplacian * s->l0;
    const double c = 2.0 * 2 / (s->lambda * s->n0_laplacian);
    const neighbour_list *nl = &s->neighbours;
    const double *position = s->state.position;
    double *pressure = s->state.pressure;

    /* Number the unknowns in particle order. */
    long unknowns = 0;
    for (size_t i = 0; i < s->count; i++)
        s->unknown_of[i] = (takes_part(s, i) && !s->on_surface[i]) ? unknowns++ : -1;
    s->ppe_unknowns = (size_t)unknowns;
    s->ppe_iterations = 0;
    s->ppe_residual = 0.0;
    if (unknowns == 0)
        return MPS2P_OK;

    /* Count the pattern: the diagonal plus unknown neighbours in range. */
    size_t entries = 0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->unknown_of[i] < 0)
            continue;
        entries++;
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            if (s->unknown_of[j] < 0)
                continue;
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            if (dx * dx + dy * dy < re * re)
                entries++;
        }
    }
    if (entries > (size_t)INT_MAX)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "pressure matrix with %zu entries is beyond the int index range", entries);
    if (grow_matrix(&s->matrix, (int)unknowns, entries) != MPS2P_OK)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "out of memory for the pressure matrix (%zu entries)", entries);

    sparse_matrix *m = &s->matrix;
    m->rows = (int)unknowns;
    int next = 0;
    for (size_t i = 0; i < s->count; i++) {
        long row = s->unknown_of[i];
        if (row < 0)
            continue;
        m->row_start[row] = next;
        int diagonal_at = -1;
        double diagonal = s->density[i] * s->params.compressibility / (dt * dt);
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            if (!takes_part(s, j))
                continue;
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            if (dx * dx + dy * dy >= re * re)
                continue;
            double w = kernel_weight(sqrt(dx * dx + dy * dy), re);
            diagonal += c * w;
            if (s->unknown_of[j] < 0)
                continue;
            if (diagonal_at < 0 && j > i)
                diagonal_at = next++; /* keep columns sorted */
            m->column[next] = (int)s->unknown_of[j];
            m->value[next] = -c * w;
            next++;
        }
        if (diagonal_at < 0)
            diagonal_at = next++;
        m->column[diagonal_at] = (int)row;
        m->value[diagonal_at] = diagonal;
        s->rhs[row] = source_term(s, i, dt);
        s->solution[row] = pressure[i]; /* warm start for CG */
    }
    m->row_start[unknowns] = next;
    return MPS2P_OK;
}

int pressure_solve(mps2p_solver *s)
{
    double *pressure = s->state.pressure;
    if (s->ppe_unknowns == 0) {
        memset(pressure, 0, s->count * sizeof *pressure);
        return MPS2P_OK;
    }
    const sparse_matrix *m = &s->matrix;
    const size_t unknowns = s->ppe_unknowns;
    size_t max_iterations = s->params.cg_max_iterations > 0.0
                                ? (size_t)s->params.cg_max_iterations
                                : 10 * unknowns + 100;
    char message[ERROR_MESSAGE_SIZE];
    size_t iterations = 0;
    double residual = 0.0;
    int status = linear_solver_solve(s->linear, m, s->rhs, s->solution,
                                     s->params.cg_tolerance, max_iterations, &iterations,
                                     &residual, message, sizeof message);
    s->ppe_iterations = iterations;
    s->ppe_iterations_total += iterations;
    s->ppe_residual = residual;
    if (status != MPS2P_OK)
        return fail(s->error, status, "step %llu at t = %.6g s: pressure solve failed: %s",
                    (unsigned long long)s->steps + 1, s->time, message);

    int clamp = s->params.clamp_negative_pressure != 0.0;
    for (size_t i = 0; i < s->count; i++) {
        double p = s->unknown_of[i] >= 0 ? s->solution[s->unknown_of[i]] : 0.0;
        pressure[i] = (clamp && p < 0.0) ? 0.0 : p;
    }
    return MPS2P_OK;
}

/* The pressure system's solvers: CHOLMOD (sparse Cholesky) or conjugate
 * gradients, preconditioned by the diagonal (Jacobi), by an incomplete
 * Cholesky factor with A's own pattern (IC(0)) or by the diagonal plus a
 * coarse correction (two-level, coarse_level.c), or, with option petsc,
 * PETSc's CG with algebraic multigrid (gamg_solver.c). None prints or
 * aborts: errors come back as status codes with a message. */
#include "numerics/numerics.h"

#include <cholmod.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_vector.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct linear_solver {
    int kind;
    int preconditioner; /* enum cg_preconditioner_kind, for CG */
    cholmod_common common;
    /* The last factor and the pattern it was analysed for: a matrix with the
     * same pattern is factorised numerically only. The ordering depends on the
     * pattern alone, so reuse gives the same bits as a fresh analysis. */
    cholmod_factor *factor;
    int *pattern_start, *pattern_column;
    int pattern_rows;
    size_t pattern_capacity; /* of pattern_column */
    uint64_t analyses;       /* symbolic analyses so far */
    double *work; /* work_vectors(): 5 for CG with Jacobi, 4 with IC(0), 1 for
                     CHOLMOD and gamg (the first serves the residual check), then
                     2 partial sums a block (REDUCTION_BLOCK) */
    size_t work_size;
    /* IC(0): L, the lower triangle of A's pattern, in compressed rows, each
     * row's diagonal last; then L^T's rows without the diagonal (the
     * backward substitution reads rows, rather than scattering into them),
     * and 1 / L's diagonal */
    int *factor_start, *factor_column, *transpose_start, *transpose_column;
    double *factor_value, *transpose_value, *inverse_pivot;
    size_t factor_capacity, factor_row_capacity;
    double threads; /* parameter threads (team_size) */
    gamg_solver *gamg; /* kind PRESSURE_SOLVER_GAMG */
    coarse_level *coarse; /* CG with CG_PRECONDITIONER_TWO_LEVEL */
};

int linear_solver_have_gamg(void)
{
#ifdef MPS2P_HAVE_PETSC
    return 1;
#else
    return 0;
#endif
}

int linear_solver_create(int kind, int preconditioner, double threads, linear_solver **out,
                         char *message, size_t size)
{
    if (kind == PRESSURE_SOLVER_GAMG && !linear_solver_have_gamg()) {
        snprintf(message, size, "pressure_solver gamg: this libmps2p was built without PETSc "
                                "(meson option petsc)");
        return MPS2P_ERR_INVALID;
    }
    linear_solver *ls = calloc(1, sizeof *ls);
    if (!ls) {
        snprintf(message, size, "out of memory starting the pressure solver");
        return MPS2P_ERR_NOMEM;
    }
    ls->kind = kind;
    ls->preconditioner = preconditioner;
    ls->threads = threads;
    if (kind == PRESSURE_SOLVER_CHOLMOD) {
        if (!cholmod_start(&ls->common)) {
            free(ls);
            snprintf(message, size, "out of memory starting the pressure solver");
            return MPS2P_ERR_NOMEM;
        }
        ls->common.print = 0;            /* never print from a library */
        ls->common.error_handler = NULL; /* errors come back in common.status */
        /* simplicial or supernodal: chosen per solve in solve_cholmod */
        /* AMD only, the ordering CHOLMOD's default picks for these matrices.
         * The default also tries METIS when AMD runs out of memory (or fills
         * in badly), silently: the step would succeed with another ordering
         * and differ in the last bits from the same run with enough memory.
         * With one method, running out of memory is an error. */
        ls->common.nmethods = 1;
        ls->common.method[0].ordering = CHOLMOD_AMD;
    }
    if (kind == PRESSURE_SOLVER_CG && preconditioner == CG_PRECONDITIONER_TWO_LEVEL) {
        int status = coarse_level_create(&ls->coarse, message, size);
        if (status != MPS2P_OK) {
            free(ls);
            return status;
        }
    }
#ifdef MPS2P_HAVE_PETSC
    if (kind == PRESSURE_SOLVER_GAMG) {
        int status = gamg_create(&ls->gamg, message, size);
        if (status != MPS2P_OK) {
            free(ls);
            return status;
        }
    }
#endif
    *out = ls;
    return MPS2P_OK;
}

void linear_solver_destroy(linear_solver *ls)
{
    if (!ls)
        return;
    if (ls->kind == PRESSURE_SOLVER_CHOLMOD) {
        cholmod_free_factor(&ls->factor, &ls->common);
        cholmod_finish(&ls->common);
    }
#ifdef MPS2P_HAVE_PETSC
    gamg_destroy(ls->gamg);
#endif
    coarse_level_destroy(ls->coarse);
    free(ls->pattern_start);
    free(ls->pattern_column);
    free(ls->work);
    free(ls->factor_start);
    free(ls->factor_column);
    free(ls->factor_value);
    free(ls->transpose_start);
    free(ls->transpose_column);
    free(ls->transpose_value);
    free(ls->inverse_pivot);
    free(ls);
}

uint64_t linear_solver_analyses(const linear_solver *ls)
{
    return ls ? ls->analyses : 0;
}

size_t linear_solver_memory(const linear_solver *ls)
{
    if (!ls)
        return 0;
    size_t bytes = sizeof *ls + ls->work_size * sizeof *ls->work;
    if (ls->pattern_start)
        bytes += ((size_t)ls->pattern_rows + 1) * sizeof *ls->pattern_start;
    bytes += ls->pattern_capacity * sizeof *ls->pattern_column;
    bytes += ls->factor_row_capacity * (2 * sizeof(int) + sizeof(double)) +
             2 * ls->factor_capacity * (sizeof(int) + sizeof(double));
    if (ls->kind == PRESSURE_SOLVER_CHOLMOD)
        bytes += ls->common.memory_inuse; /* what CHOLMOD holds, the kept factor too */
    bytes += coarse_level_memory(ls->coarse);
#ifdef MPS2P_HAVE_PETSC
    bytes += gamg_memory(ls->gamg);
#endif
    return bytes;
}

/* A loop over a matrix's rows (the product, the diagonal's inverse) with
 * fewer rows than a block stays on the calling thread: a fork costs more
 * than the loop. A vector loop of its own (a few nanoseconds a row) stays
 * there below VECTOR_PARALLEL_FROM rows: at 4,700 (the paper's gas) a team
 * started for each took twice as long as one thread (docs/performance.md).
 * CG's iterations share theirs in one team from PARALLEL_FROM rows on
 * (cg_iterations). */
#define PARALLEL_FROM REDUCTION_BLOCK
#define VECTOR_PARALLEL_FROM (8 * REDUCTION_BLOCK)

/* Room for partial sums a block: dot, the residual check and the coarse
 * correction of CG's start use two a block (partial[2 b + part], combine);
 * CG's iterations four (partial[PARTIAL_SLOTS b + slot], combine_slot): r.z,
 * r.r, p.q and the coarse correction's r.z, each in its own slot. */
#define PARTIAL_SLOTS 4

static size_t block_count(size_t n)
{
    return (n + REDUCTION_BLOCK - 1) / REDUCTION_BLOCK;
}

/* Work vectors of n: CG's r, z, p, q, and with Jacobi (two-level too) its
 * inverse diagonal;
 * the direct and multigrid solves only the residual check's product. */
static size_t work_vectors(const linear_solver *ls)
{
    if (ls->kind != PRESSURE_SOLVER_CG)
        return 1;
    return ls->preconditioner == CG_PRECONDITIONER_IC0 ? 4 : 5;
}

static double *partial_sums(const linear_solver *ls, size_t n)
{
    return ls->work + work_vectors(ls) * n;
}

/* The sum of value[k] x[column[k]] for k in [first, end): four sums in turn,
 * not one, since one chain of dependent adds would wait on each add's latency. */
static inline double sparse_dot(const double *value, const int *column, int first, int end,
                                const double *x)
{
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    int k = first;
    for (; k + 4 <= end; k += 4)
        for (int lane = 0; lane < 4; lane++)
            sum[lane] += value[k + lane] * x[column[k + lane]];
    for (; k < end; k++)
        sum[0] += value[k] * x[column[k]];
    return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

static void multiply(const linear_solver *ls, const sparse_matrix *a, const double *x,
                     double *y)
{
    PARALLEL_FOR(ls->threads, schedule(static) if (a->rows >= PARALLEL_FROM),
    for (int i = 0; i < a->rows; i++) {
        y[i] = sparse_dot(a->value, a->column, a->row_start[i], a->row_start[i + 1], x);
    });
}

/* Adds the block sums partial[2 b + part] in block order. */
static double combine(const double *partial, size_t blocks, int part)
{
    double sum = 0.0;
    for (size_t b = 0; b < blocks; b++)
        sum += partial[2 * b + (size_t)part];
    return sum;
}

/* x . y over block b of REDUCTION_BLOCK entries, summed in order by GSL.
 * GSL's error handler is process-wide and the host's to set (its default
 * aborts), so the library leaves it alone and calls GSL only where it cannot
 * fail: every view here is non-empty (a block holds 1 to REDUCTION_BLOCK
 * entries) and the two lengths agree. */
static double block_dot(const double *x, const double *y, size_t n, size_t b)
{
    size_t first = b * REDUCTION_BLOCK;
    size_t length = n - first < REDUCTION_BLOCK ? n - first : REDUCTION_BLOCK;
    gsl_vector_const_view xv = gsl_vector_const_view_array(x + first, length);
    gsl_vector_const_view yv = gsl_vector_const_view_array(y + first, length);
    double sum = 0.0;
    gsl_blas_ddot(&xv.vector, &yv.vector, &sum); /* lengths agree: no error */
    return sum;
}

/* x . y over fixed blocks, the blocks combined in order: the same bits for
 * any number of threads. */
static double dot(const linear_solver *ls, const double *x, const double *y, size_t n)
{
    const size_t blocks = block_count(n);
    double *partial = partial_sums(ls, n);
    PARALLEL_FOR(ls->threads, schedule(static) if (n >= VECTOR_PARALLEL_FROM),
    for (size_t b = 0; b < blocks; b++) {
        partial[2 * b] = block_dot(x, y, n, b);
    });
    return combine(partial, blocks, 0);
}

static double relative_residual(const linear_solver *ls, const sparse_matrix *a,
                                const double *b, const double *x)
{
    const size_t n = (size_t)a->rows, blocks = block_count(n);
    double *work = ls->work, *partial = partial_sums(ls, n);
    multiply(ls, a, x, work);
    PARALLEL_FOR(ls->threads, schedule(static) if (n >= VECTOR_PARALLEL_FROM),
    for (size_t block = 0; block < blocks; block++) {
        size_t first = block * REDUCTION_BLOCK;
        size_t end = n - first < REDUCTION_BLOCK ? n : first + REDUCTION_BLOCK;
        double r2 = 0.0, b2 = 0.0;
        for (size_t i = first; i < end; i++) {
            double r = b[i] - work[i];
            r2 += r * r;
            b2 += b[i] * b[i];
        }
        partial[2 * block] = r2;
        partial[2 * block + 1] = b2;
    });
    double r2 = combine(partial, blocks, 0), b2 = combine(partial, blocks, 1);
    return b2 > 0.0 ? sqrt(r2 / b2) : sqrt(r2);
}

static int ensure_work(linear_solver *ls, size_t rows)
{
    size_t size = work_vectors(ls) * rows + PARTIAL_SLOTS * block_count(rows);
    if (ls->work_size >= size)
        return MPS2P_OK;
    double *work = realloc(ls->work, size * sizeof *work);
    if (!work)
        return MPS2P_ERR_NOMEM;
    ls->work = work;
    ls->work_size = size;
    return MPS2P_OK;
}

#define SUPERNODAL_FROM_ROWS 3000

static int same_pattern(const linear_solver *ls, const sparse_matrix *a)
{
    if (!ls->factor || ls->pattern_rows != a->rows)
        return 0;
    size_t rows = (size_t)a->rows, entries = (size_t)a->row_start[a->rows];
    return memcmp(ls->pattern_start, a->row_start, (rows + 1) * sizeof *a->row_start) == 0 &&
           memcmp(ls->pattern_column, a->column, entries * sizeof *a->column) == 0;
}

static int remember_pattern(linear_solver *ls, const sparse_matrix *a)
{
    size_t rows = (size_t)a->rows, entries = (size_t)a->row_start[a->rows];
    int *start = realloc(ls->pattern_start, (rows + 1) * sizeof *start);
    if (!start)
        return MPS2P_ERR_NOMEM;
    ls->pattern_start = start;
    if (entries > ls->pattern_capacity) {
        int *column = realloc(ls->pattern_column, entries * sizeof *column);
        if (!column)
            return MPS2P_ERR_NOMEM;
        ls->pattern_column = column;
        ls->pattern_capacity = entries;
    }
    memcpy(ls->pattern_start, a->row_start, (rows + 1) * sizeof *start);
    memcpy(ls->pattern_column, a->column, entries * sizeof *a->column);
    ls->pattern_rows = a->rows;
    return MPS2P_OK;
}

static int solve_cholmod(linear_solver *ls, const sparse_matrix *a, const double *b,
                         double *x, char *message, size_t size)
{
    cholmod_common *c = &ls->common;
    /* Compressed rows of a symmetric matrix are its compressed columns;
     * stype = 1 tells CHOLMOD to read the upper triangle only. */
    cholmod_sparse matrix = {0};
    matrix.nrow = matrix.ncol = (size_t)a->rows;
    matrix.nzmax = (size_t)a->row_start[a->rows];
    matrix.p = a->row_start;
    matrix.i = a->column;
    matrix.x = a->value;
    matrix.stype = 1;
    matrix.itype = CHOLMOD_INT;
    matrix.xtype = CHOLMOD_REAL;
    matrix.dtype = CHOLMOD_DOUBLE;
    matrix.sorted = 1;
    matrix.packed = 1;

    /* Small systems factorise faster simplicial (measured: the 0.15 m dam break
     * at l0 = 0.01, about 450 unknowns, 1.6 s against 2.0 s), large ones
     * supernodal (the 1 m x 2 m column at l0 = 0.02, about 5000 unknowns,
     * 122-132 ms a step against 251 ms); CHOLMOD's own rule picks supernodal
     * too early here. */
    c->supernodal = a->rows < SUPERNODAL_FROM_ROWS ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO;
    if (!same_pattern(ls, a)) {
        cholmod_free_factor(&ls->factor, c);
        ls->pattern_rows = -1;
        ls->factor = cholmod_analyze(&matrix, c);
        ls->analyses++;
        if (!ls->factor) {
            snprintf(message, size, "CHOLMOD analysis failed (status %d)", c->status);
            return c->status == CHOLMOD_OUT_OF_MEMORY ? MPS2P_ERR_NOMEM : MPS2P_ERR_SOLVE;
        }
        if (remember_pattern(ls, a) != MPS2P_OK)
            ls->pattern_rows = -1; /* no copy: analyse again next time */
    }
    cholmod_factor *factor = ls->factor;
    cholmod_factorize(&matrix, factor, c);
    if (c->status != CHOLMOD_OK || factor->minor < factor->n) {
        snprintf(message, size,
                 "CHOLMOD factorization failed: %s (status %d, pivot %zu of %zu)",
                 c->status == CHOLMOD_NOT_POSDEF || factor->minor < factor->n
                     ? "matrix not positive definite"
                     : "error",
                 c->status, (size_t)factor->minor, (size_t)factor->n);
        int status = c->status == CHOLMOD_OUT_OF_MEMORY ? MPS2P_ERR_NOMEM : MPS2P_ERR_SOLVE;
        cholmod_free_factor(&ls->factor, c); /* a failed factor is not reused */
        ls->pattern_rows = -1;
        return status;
    }
    cholmod_dense rhs = {0};
    rhs.nrow = rhs.d = rhs.nzmax = (size_t)a->rows;
    rhs.ncol = 1;
    rhs.x = (void *)b;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *solution = cholmod_solve(CHOLMOD_A, factor, &rhs, c);
    if (!solution) {
        snprintf(message, size, "CHOLMOD solve failed (status %d)", c->status);
        return c->status == CHOLMOD_OUT_OF_MEMORY ? MPS2P_ERR_NOMEM : MPS2P_ERR_SOLVE;
    }
    const double *values = solution->x;
    for (int i = 0; i < a->rows; i++)
        x[i] = values[i];
    cholmod_free_dense(&solution, c);
    return MPS2P_OK;
}

/* Room for L and L^T: as many rows as A, and A's lower triangle. */
static int ensure_factor(linear_solver *ls, size_t rows, size_t entries)
{
    if (rows + 1 > ls->factor_row_capacity) {
        if (!grow(&ls->factor_start, rows + 1, sizeof(int)) ||
            !grow(&ls->transpose_start, rows + 1, sizeof(int)) ||
            !grow(&ls->inverse_pivot, rows + 1, sizeof(double)))
            return MPS2P_ERR_NOMEM;
        ls->factor_row_capacity = rows + 1;
    }
    if (entries > ls->factor_capacity) {
        if (!grow(&ls->factor_column, entries, sizeof(int)) ||
            !grow(&ls->factor_value, entries, sizeof(double)) ||
            !grow(&ls->transpose_column, entries, sizeof(int)) ||
            !grow(&ls->transpose_value, entries, sizeof(double)))
            return MPS2P_ERR_NOMEM;
        ls->factor_capacity = entries;
    }
    return MPS2P_OK;
}

/* IC(0) (Meijerink and van der Vorst): L with the lower pattern of A and
 * L L^T = A on that pattern, row by row. The PPE matrices are M-matrices
 * (positive diagonal, off-diagonal entries <= 0, diagonally dominant), for
 * which it exists; should a pivot still come out non-positive (rounding),
 * A's diagonal entry stands in for it, so L L^T stays positive definite and
 * CG converges, if more slowly. Serial: the same bits for any threads. */
static int factor_ic0(linear_solver *ls, const sparse_matrix *a, char *message, size_t size)
{
    const int n = a->rows;
    size_t entries = 0;
    for (int i = 0; i < n; i++)
        for (int k = a->row_start[i]; k < a->row_start[i + 1]; k++)
            entries += a->column[k] <= i;
    if (ensure_factor(ls, (size_t)n, entries) != MPS2P_OK) {
        snprintf(message, size, "out of memory for the IC(0) factor (%zu entries)", entries);
        return MPS2P_ERR_NOMEM;
    }
    int *start = ls->factor_start, *column = ls->factor_column;
    double *value = ls->factor_value;
    int next = 0;
    for (int i = 0; i < n; i++) {
        start[i] = next;
        int diagonal = -1;
        for (int k = a->row_start[i]; k < a->row_start[i + 1] && a->column[k] <= i; k++) {
            column[next] = a->column[k];
            value[next] = a->value[k];
            if (a->column[k] == i)
                diagonal = next;
            next++;
        }
        if (diagonal != next - 1 || !(value[diagonal] > 0.0)) {
            snprintf(message, size, "CG: diagonal entry %d is %g, not positive", i,
                     diagonal == next - 1 ? value[diagonal] : 0.0);
            return MPS2P_ERR_SOLVE;
        }
    }
    start[n] = next;
    /* row i's finished entries, scattered by column (zero elsewhere), so that
     * its products with row k are a gather, not a merge */
    double *row_i = ls->work + (size_t)n;
    memset(row_i, 0, (size_t)n * sizeof *row_i);
    for (int i = 0; i < n; i++) {
        const int first = start[i], diagonal = start[i + 1] - 1;
        for (int e = first; e < diagonal; e++) {
            /* L_ik = (A_ik - sum over j < k of L_ij L_kj) / L_kk */
            const int k = column[e], k_diagonal = start[k + 1] - 1;
            double sum = value[e] - sparse_dot(value, column, start[k], k_diagonal, row_i);
            value[e] = sum * ls->inverse_pivot[k];
            row_i[k] = value[e];
        }
        for (int e = first; e < diagonal; e++)
            row_i[column[e]] = 0.0;
        double pivot = value[diagonal];
        for (int e = first; e < diagonal; e++)
            pivot -= value[e] * value[e];
        value[diagonal] = sqrt(pivot > 0.0 ? pivot : value[diagonal]);
        ls->inverse_pivot[i] = 1.0 / value[diagonal];
    }
    /* L^T by rows, the diagonal left out: a counting sort by column, which
     * keeps each of its rows in ascending order */
    int *t_start = ls->transpose_start, *t_column = ls->transpose_column;
    double *t_value = ls->transpose_value;
    memset(t_start, 0, ((size_t)n + 1) * sizeof *t_start);
    for (int i = 0; i < n; i++)
        for (int e = start[i]; e < start[i + 1] - 1; e++)
            t_start[column[e] + 1]++;
    for (int i = 0; i < n; i++)
        t_start[i + 1] += t_start[i];
    for (int i = 0; i < n; i++)
        for (int e = start[i]; e < start[i + 1] - 1; e++) {
            int at = t_start[column[e]]++;
            t_column[at] = i;
            t_value[at] = value[e];
        }
    for (int i = n; i > 0; i--) /* the cursors back to row starts */
        t_start[i] = t_start[i - 1];
    t_start[0] = 0;
    return MPS2P_OK;
}

/* z = (L L^T)^-1 r: forward, then backward substitution. */
static void apply_ic0(const linear_solver *ls, size_t n, const double *r, double *z)
{
    const int *start = ls->factor_start, *column = ls->factor_column;
    const int *t_start = ls->transpose_start, *t_column = ls->transpose_column;
    const double *value = ls->factor_value, *t_value = ls->transpose_value;
    const double *inverse_pivot = ls->inverse_pivot;
    for (size_t i = 0; i < n; i++)
        z[i] = (r[i] - sparse_dot(value, column, start[i], start[i + 1] - 1, z)) *
               inverse_pivot[i];
    for (size_t i = n; i-- > 0;)
        z[i] = (z[i] - sparse_dot(t_value, t_column, t_start[i], t_start[i + 1], z)) *
               inverse_pivot[i];
}

/* The sum of the slot's block sums, in block order (stride PARTIAL_SLOTS). */
static double combine_slot(const double *partial, size_t blocks, int slot)
{
    double sum = 0.0;
    for (size_t b = 0; b < blocks; b++)
        sum += partial[PARTIAL_SLOTS * b + (size_t)slot];
    return sum;
}

enum { SLOT_RZ, SLOT_RR, SLOT_PQ, SLOT_COARSE_RZ };

/* CG's state while it iterates, shared by a team's threads. */
typedef struct cg_run {
    linear_solver *ls;
    const sparse_matrix *a;
    double *x, *r, *z, *p, *q, *inverse_diagonal, *partial;
    size_t n, blocks, max_iterations;
    double tolerance, b_norm, rr, rz;
    int incomplete_cholesky, two_level;
    const double *coarse;      /* the coarse solve's answer (thread 0's) */
    const int *aggregate_of;
    double ic0_rz;             /* r . z after IC(0) (thread 0's) */
    size_t iterations;
    int status;
} cg_run;

/* A barrier for a team of more than one; a team of one never enters libgomp
 * (numerics.h: PARALLEL_FOR). */
#ifdef _OPENMP
#define TEAM_BARRIER(team)                                                     \
    do {                                                                       \
        if ((team) > 1) {                                                      \
            _Pragma("omp barrier")                                             \
        }                                                                      \
    } while (0)
#else
#define TEAM_BARRIER(team) (void)(team)
#endif

/* CG's iterations, by thread `thread` of a team of `team`: a thread takes
 * rows [n t / team, n (t + 1) / team) of the product and the search
 * direction, and blocks [B t / team, B (t + 1) / team) of the sums; each
 * block sums in order and every thread adds the block sums in block order,
 * so every thread computes the same scalars, and the result is the same bits
 * for any team (one thread: the plain loop). One parallel region for all the
 * iterations, its threads meeting at barriers: a vector loop over the gas's
 * 4,700 rows is a few microseconds, less than starting a team for it. */
static void cg_iterations(cg_run *run, int thread, int team)
{
    const sparse_matrix *a = run->a;
    const size_t n = run->n, blocks = run->blocks;
    const size_t row0 = n * (size_t)thread / (size_t)team;
    const size_t row1 = n * (size_t)(thread + 1) / (size_t)team;
    const size_t block0 = blocks * (size_t)thread / (size_t)team;
    const size_t block1 = blocks * (size_t)(thread + 1) / (size_t)team;
    double *x = run->x, *r = run->r, *z = run->z, *p = run->p, *q = run->q;
    const double *inverse_diagonal = run->inverse_diagonal;
    double *partial = run->partial;
    const int incomplete_cholesky = run->incomplete_cholesky;
    const double bound = run->tolerance * run->b_norm;
    /* With the coarse level and a team, x moves while the first thread
     * solves the coarse system: by the other threads, each its share of the
     * rows, also in the last iteration (alone then) */
    const int defer_x = run->two_level && team > 1;
    const size_t x_row0 = thread == 0 ? 0 : n * (size_t)(thread - 1) / (size_t)(team - 1);
    const size_t x_row1 = thread == 0 ? 0 : n * (size_t)thread / (size_t)(team - 1);
    double rr = run->rr, rz = run->rz;
    size_t k = 0;
    int status = MPS2P_ERR_SOLVE;
    for (;;) {
        if (sqrt(rr) <= bound) {
            status = MPS2P_OK;
            break;
        }
        if (k >= run->max_iterations)
            break;
        for (size_t i = row0; i < row1; i++)
            q[i] = sparse_dot(a->value, a->column, a->row_start[i], a->row_start[i + 1], p);
        TEAM_BARRIER(team);
        for (size_t b = block0; b < block1; b++)
            partial[PARTIAL_SLOTS * b + SLOT_PQ] = block_dot(p, q, n, b);
        TEAM_BARRIER(team);
        double pq = combine_slot(partial, blocks, SLOT_PQ);
        if (!(pq > 0.0))
            break;
        double alpha = rz / pq;
        /* x += alpha p (unless deferred), r -= alpha q, z = M^-1 r, and the
         * block sums of r.z and r.r, in one pass over each block */
        for (size_t b = block0; b < block1; b++) {
            size_t first = b * REDUCTION_BLOCK;
            size_t end = n - first < REDUCTION_BLOCK ? n : first + REDUCTION_BLOCK;
            double block_rz = 0.0, block_rr = 0.0;
            for (size_t i = first; i < end; i++) {
                if (!defer_x)
                    x[i] += alpha * p[i];
                r[i] += -alpha * q[i];
                if (!incomplete_cholesky) {
                    z[i] = r[i] * inverse_diagonal[i];
                    block_rz += r[i] * z[i];
                }
                block_rr += r[i] * r[i];
            }
            partial[PARTIAL_SLOTS * b + SLOT_RZ] = block_rz;
            partial[PARTIAL_SLOTS * b + SLOT_RR] = block_rr;
        }
        TEAM_BARRIER(team);
        rr = combine_slot(partial, blocks, SLOT_RR);
        double rz_next = combine_slot(partial, blocks, SLOT_RZ);
        if (incomplete_cholesky) {
            /* the triangular solves are sequential: thread 0's */
            if (thread == 0) {
                apply_ic0(run->ls, n, r, z);
                /* r . z as dot() sums it, without its partial sums (the
                 * team may still be reading this iteration's) */
                double total = 0.0;
                for (size_t b = 0; b < blocks; b++)
                    total += block_dot(r, z, n, b);
                run->ic0_rz = total;
            }
            TEAM_BARRIER(team);
            rz_next = run->ic0_rz;
        } else if (run->two_level && sqrt(rr) > bound) {
            /* (not when converged: the loop stops before using z). Each
             * thread restricts the aggregates that start in its blocks
             * (mostly its own rows of r), then the first solves the coarse
             * system while the others move x (deferred: nothing reads it
             * before the end) */
            coarse_level *coarse_level = run->ls->coarse;
            if (team > 1) {
                coarse_level_restrict(coarse_level, r, block0 * REDUCTION_BLOCK,
                                      block1 * REDUCTION_BLOCK);
                TEAM_BARRIER(team);
            }
            if (thread == 0)
                run->coarse = team > 1
                                  ? coarse_level_solve_restricted(coarse_level, &run->aggregate_of)
                                  : coarse_level_solve(coarse_level, r, &run->aggregate_of);
            else
                for (size_t i = x_row0; i < x_row1; i++)
                    x[i] += alpha * p[i];
            TEAM_BARRIER(team);
            const double *coarse = run->coarse;
            if (!coarse) {
                status = MPS2P_ERR_NOMEM;
                break;
            }
            const int *aggregate_of = run->aggregate_of;
            for (size_t b = block0; b < block1; b++) {
                size_t first = b * REDUCTION_BLOCK;
                size_t end = n - first < REDUCTION_BLOCK ? n : first + REDUCTION_BLOCK;
                double block_rz = 0.0;
                for (size_t i = first; i < end; i++) {
                    z[i] += coarse[aggregate_of[i]];
                    block_rz += r[i] * z[i];
                }
                partial[PARTIAL_SLOTS * b + SLOT_COARSE_RZ] = block_rz;
            }
            TEAM_BARRIER(team);
            rz_next = combine_slot(partial, blocks, SLOT_COARSE_RZ);
        } else if (defer_x) { /* converged: x's last move, and the end (every
                                 thread sees the same rr) before p changes */
            for (size_t i = x_row0; i < x_row1; i++)
                x[i] += alpha * p[i];
            k++;
            status = MPS2P_OK;
            break;
        }
        double beta = rz_next / rz;
        rz = rz_next;
        for (size_t i = row0; i < row1; i++)
            p[i] = p[i] * beta + z[i];
        TEAM_BARRIER(team); /* the next product reads every row of p */
        k++;
    }
    if (thread == 0) {
        run->iterations = k;
        run->status = status;
        run->rr = rr;
    }
}

/* z += P A_c^-1 P^T r, and r . z (block sums in order, as dot). */
static int add_coarse_correction(const linear_solver *ls, const double *r, double *z,
                                 size_t n, double *rz, char *message, size_t size)
{
    const int *aggregate_of = NULL;
    const double *coarse = coarse_level_solve(ls->coarse, r, &aggregate_of);
    if (!coarse) {
        snprintf(message, size, "two-level preconditioner: the coarse solve failed (out of "
                                "memory, or no coarse factor)");
        return MPS2P_ERR_NOMEM;
    }
    const size_t blocks = block_count(n);
    double *partial = partial_sums(ls, n);
    PARALLEL_FOR(ls->threads, schedule(static) if (n >= VECTOR_PARALLEL_FROM),
    for (size_t block = 0; block < blocks; block++) {
        size_t first = block * REDUCTION_BLOCK;
        size_t end = n - first < REDUCTION_BLOCK ? n : first + REDUCTION_BLOCK;
        double block_rz = 0.0;
        for (size_t i = first; i < end; i++) {
            z[i] += coarse[aggregate_of[i]];
            block_rz += r[i] * z[i];
        }
        partial[2 * block] = block_rz;
    });
    *rz = combine(partial, blocks, 0);
    return MPS2P_OK;
}

/* Row i's diagonal entry (0 when it has none). */
static double diagonal_entry(const sparse_matrix *a, size_t i)
{
    double d = 0.0;
    for (int k = a->row_start[i]; k < a->row_start[i + 1]; k++)
        if ((size_t)a->column[k] == i)
            d = a->value[k];
    return d;
}

static int solve_cg(linear_solver *ls, const sparse_matrix *a, const double *b, double *x,
                    double tolerance, size_t max_iterations, size_t *iterations,
                    char *message, size_t size)
{
    const size_t n = (size_t)a->rows, blocks = block_count(n);
    double *r = ls->work, *z = r + n, *p = z + n, *q = p + n;
    /* Jacobi's only: with IC(0) the partial sums lie there (work_vectors) */
    double *inverse_diagonal = ls->preconditioner == CG_PRECONDITIONER_IC0 ? NULL : q + n;
    double *partial = partial_sums(ls, n);

    double b_norm = sqrt(dot(ls, b, b, n));
    if (b_norm == 0.0) {
        memset(x, 0, n * sizeof *x);
        *iterations = 0;
        return MPS2P_OK;
    }
    multiply(ls, a, x, q);
    for (size_t i = 0; i < n; i++)
        r[i] = b[i] - q[i];
    const int incomplete_cholesky = ls->preconditioner == CG_PRECONDITIONER_IC0;
    if (incomplete_cholesky) {
        int status = factor_ic0(ls, a, message, size);
        if (status != MPS2P_OK)
            return status;
        apply_ic0(ls, n, r, z);
        memcpy(p, z, n * sizeof *p);
    }
    /* Jacobi preconditioner: the inverse of each row's diagonal entry */
    int not_positive = 0;
    if (!incomplete_cholesky)
        PARALLEL_FOR(ls->threads,
                     schedule(static) reduction(| : not_positive) if (a->rows >= PARALLEL_FROM),
        for (size_t i = 0; i < n; i++) {
            double d = diagonal_entry(a, i);
            not_positive |= !(d > 0.0);
            inverse_diagonal[i] = 1.0 / d;
            z[i] = r[i] * inverse_diagonal[i];
            p[i] = z[i];
        });
    for (size_t i = 0; i < n && not_positive; i++) {
        double d = diagonal_entry(a, i);
        if (!(d > 0.0)) {
            snprintf(message, size, "CG: diagonal entry %zu is %g, not positive", i, d);
            return MPS2P_ERR_SOLVE;
        }
    }
    /* (no set-up when the warm start already meets the tolerance: still water) */
    double rr = dot(ls, r, r, n), rz = 0.0;
    const int two_level = ls->preconditioner == CG_PRECONDITIONER_TWO_LEVEL &&
                          sqrt(rr) > tolerance * b_norm;
    if (two_level) {
        int status = coarse_level_setup(ls->coarse, a, ls->threads, message, size);
        if (status == MPS2P_OK)
            status = add_coarse_correction(ls, r, z, n, &rz, message, size);
        if (status != MPS2P_OK)
            return status;
        memcpy(p, z, n * sizeof *p);
    } else {
        rz = dot(ls, r, z, n);
    }
    cg_run run = {.ls = ls, .a = a, .x = x, .r = r, .z = z, .p = p, .q = q,
                  .inverse_diagonal = inverse_diagonal, .partial = partial, .n = n,
                  .blocks = blocks, .max_iterations = max_iterations,
                  .tolerance = tolerance, .b_norm = b_norm, .rr = rr, .rz = rz,
                  .incomplete_cholesky = incomplete_cholesky, .two_level = two_level};
    /* a team from a block of rows on, as the product's */
    const int team = a->rows >= PARALLEL_FROM ? team_size(ls->threads) : 1;
    (void)team; /* without OpenMP */
#ifdef _OPENMP
    if (team > 1) {
        _Pragma("omp parallel num_threads(team)")
        cg_iterations(&run, omp_get_thread_num(), omp_get_num_threads());
    } else
#endif
        cg_iterations(&run, 0, 1);
    size_t k = run.iterations;
    int status = run.status;
    rr = run.rr;
    if (status == MPS2P_ERR_NOMEM) {
        *iterations = k;
        snprintf(message, size, "two-level preconditioner: the coarse solve failed (out of "
                                "memory, or no coarse factor)");
        return status;
    }
    *iterations = k;
    if (status != MPS2P_OK)
        snprintf(message, size,
                 "CG did not converge: %zu iterations, residual %g of |b|, tolerance %g", k,
                 sqrt(rr) / b_norm, tolerance);
    return status;
}

int linear_solver_solve(linear_solver *ls, const sparse_matrix *a, const double *b,
                        double *x, double tolerance, size_t max_iterations,
                        size_t *iterations, double *residual, char *message, size_t size)
{
    *iterations = 0;
    *residual = 0.0;
    if (ensure_work(ls, (size_t)a->rows) != MPS2P_OK) {
        snprintf(message, size, "out of memory for solver work space");
        return MPS2P_ERR_NOMEM;
    }
    int status;
    if (ls->kind == PRESSURE_SOLVER_CHOLMOD)
        status = solve_cholmod(ls, a, b, x, message, size);
#ifdef MPS2P_HAVE_PETSC
    else if (ls->kind == PRESSURE_SOLVER_GAMG)
        status = gamg_solve(ls->gamg, a, b, x, tolerance, max_iterations, iterations, message,
                            size);
#endif
    else
        status = solve_cg(ls, a, b, x, tolerance, max_iterations, iterations, message, size);
    if (status != MPS2P_OK)
        return status;
    *residual = relative_residual(ls, a, b, x);
    /* A direct solve of an SPD system is accurate to rounding; anything else
     * means the factorization went wrong. */
    double accepted = ls->kind == PRESSURE_SOLVER_CHOLMOD ? 1e-6 : 10.0 * tolerance + 1e-12;
    if (!(*residual <= accepted)) {
        snprintf(message, size, "solution has relative residual %g (accepted %g)",
                 *residual, accepted);
        return MPS2P_ERR_SOLVE;
    }
    return MPS2P_OK;
}

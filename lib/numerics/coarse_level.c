/* The coarse level of CG's two-level preconditioner (cg_preconditioner =
 * two_level): z = D^-1 r + P A_c^-1 P^T r, the diagonal plus a correction on
 * aggregates of neighbouring unknowns. P is piecewise constant (an unknown
 * takes its aggregate's value), A_c = P^T A P the Galerkin coarse matrix,
 * factorised by CHOLMOD. Jacobi alone damps only the short waves of the
 * error, so its iterations grow with the size of a region without a free
 * surface (the air over the water: 87 a step in the paper's case); the
 * coarse level takes the long ones (docs/performance.md). The aggregates
 * are those of unsmoothed aggregation multigrid: a greedy pass over A's
 * graph, every unknown with its neighbours, serial and in row order; A_c's
 * columns are built in runs, one a thread, each column as one thread builds
 * it: the same bits for any number of threads. */
#include "numerics/numerics.h"

#include <cholmod.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct coarse_level {
    cholmod_common common;
    cholmod_factor *factor;
    cholmod_dense *solution, *work_y, *work_e; /* cholmod_solve2's, reused */
    int *aggregate_of;                         /* of each unknown */
    int *member_start, *member;                /* the unknowns of each aggregate */
    int *lead_order; /* the aggregates in the order of their first unknowns */
    int *coarse_start, *coarse_row, *marker;   /* A_c's upper triangle, by columns */
    double *coarse_value, *accumulated, *restricted;
    size_t rows_capacity, count_capacity, entries_capacity;
    int rows, count;
};

/* CHOLMOD's simplicial factor is faster than the supernodal one on small
 * systems (linear_solver.c measures the rule for the fine system). */
#define SUPERNODAL_FROM_ROWS 3000

int coarse_level_create(coarse_level **out, char *message, size_t size)
{
    coarse_level *c = calloc(1, sizeof *c);
    if (!c || !cholmod_start(&c->common)) {
        free(c);
        snprintf(message, size, "out of memory starting the two-level preconditioner");
        return MPS2P_ERR_NOMEM;
    }
    c->common.print = 0;            /* never print from a library */
    c->common.error_handler = NULL; /* errors come back in common.status */
    c->common.nmethods = 1;         /* AMD alone: no silent switch to METIS */
    c->common.method[0].ordering = CHOLMOD_AMD;
    /* L L^T, not L D L^T: a simplicial LDL^T factor reports only a zero
     * pivot, and a coarse matrix that is not positive definite (a system
     * without a free surface and compressibility 0) must fail here */
    c->common.final_ll = 1;
    *out = c;
    return MPS2P_OK;
}

void coarse_level_destroy(coarse_level *c)
{
    if (!c)
        return;
    cholmod_free_factor(&c->factor, &c->common);
    cholmod_free_dense(&c->solution, &c->common);
    cholmod_free_dense(&c->work_y, &c->common);
    cholmod_free_dense(&c->work_e, &c->common);
    cholmod_finish(&c->common);
    free(c->aggregate_of);
    free(c->member_start);
    free(c->member);
    free(c->lead_order);
    free(c->coarse_start);
    free(c->coarse_row);
    free(c->marker);
    free(c->coarse_value);
    free(c->accumulated);
    free(c->restricted);
    free(c);
}

size_t coarse_level_memory(const coarse_level *c)
{
    if (!c)
        return 0;
    return sizeof *c + c->rows_capacity * 2 * sizeof(int) +
           c->count_capacity * (4 * sizeof(int) + 2 * sizeof(double)) +
           c->entries_capacity * (sizeof(int) + sizeof(double)) + c->common.memory_inuse;
}

/* Greedy aggregation: an unknown none of whose neighbours is taken starts
 * an aggregate with all of them; the rest join the aggregate of their
 * strongest taken neighbour (or one of their own if they have none).
 * Returns the number of aggregates. */
static int aggregate(const sparse_matrix *a, int *restrict aggregate_of)
{
    /* the matrix in locals: the stores into aggregate_of would otherwise
     * make the compiler load a's arrays again at every entry */
    const int n = a->rows;
    const int *restrict row_start = a->row_start, *restrict column = a->column;
    const double *restrict value = a->value;
    int count = 0;
    for (int i = 0; i < n; i++)
        aggregate_of[i] = -1;
    for (int i = 0; i < n; i++) {
        if (aggregate_of[i] >= 0)
            continue;
        int untaken = 1;
        for (int k = row_start[i]; k < row_start[i + 1] && untaken; k++)
            untaken = value[k] == 0.0 || aggregate_of[column[k]] < 0;
        if (!untaken)
            continue;
        /* every neighbour (measured: also the strongest only, those with at
         * least a quarter of the largest coupling, gave fewer iterations but
         * no faster solve) */
        for (int k = row_start[i]; k < row_start[i + 1]; k++)
            if (value[k] != 0.0) /* ppe_pattern neighbour_list stores zeros */
                aggregate_of[column[k]] = count;
        aggregate_of[i] = count++;
    }
    for (int i = 0; i < n; i++) {
        if (aggregate_of[i] >= 0)
            continue;
        double strongest = 0.0;
        int joined = -1;
        for (int k = row_start[i]; k < row_start[i + 1]; k++) {
            int j = column[k];
            if (j != i && aggregate_of[j] >= 0 && -value[k] > strongest) {
                strongest = -value[k];
                joined = aggregate_of[j];
            }
        }
        aggregate_of[i] = joined >= 0 ? joined : count++;
    }
    return count;
}

/* The unknowns of each aggregate, in ascending order (a counting sort). */
static void group_members(coarse_level *c, int n)
{
    int *start = c->member_start;
    memset(start, 0, ((size_t)c->count + 1) * sizeof *start);
    for (int i = 0; i < n; i++)
        start[c->aggregate_of[i] + 1]++;
    for (int g = 0; g < c->count; g++)
        start[g + 1] += start[g];
    for (int i = 0; i < n; i++)
        c->member[start[c->aggregate_of[i]]++] = i;
    for (int g = c->count; g > 0; g--)
        start[g] = start[g - 1];
    start[0] = 0;
    int lead = 0;
    for (int i = 0; i < n; i++) {
        const int g = c->aggregate_of[i];
        if (c->member[start[g]] == i)
            c->lead_order[lead++] = g;
    }
}

static int compare_int(const void *x, const void *y)
{
    int a = *(const int *)x, b = *(const int *)y;
    return (a > b) - (a < b);
}

/* Where a run of A_c's columns is built: its entries, their room, and a
 * marker and sums over the aggregates. */
typedef struct column_run {
    int *row;
    double *value;
    size_t capacity, entries;
    int *marker;
    double *accumulated;
} column_run;

/* Columns [first, end) of A_c's upper triangle: column J holds sum over i in
 * J, j in I of a_ij for every aggregate I <= J, its rows ascending, stored
 * one after another from the run's start (coarse_start gets the offsets
 * within the run). The room grows as needed (a column has at most as many
 * entries as its members' rows). */
static int build_columns(const coarse_level *c, const sparse_matrix *a, int first, int end,
                         column_run *run)
{
    size_t entries = 0;
    for (int g = 0; g < c->count; g++)
        run->marker[g] = -1;
    for (int g = first; g < end; g++) {
        size_t most = 0;
        for (int m = c->member_start[g]; m < c->member_start[g + 1]; m++)
            most += (size_t)(a->row_start[c->member[m] + 1] - a->row_start[c->member[m]]);
        if (entries + most > run->capacity) {
            size_t capacity = 2 * (entries + most);
            if (!grow(&run->row, capacity, sizeof(int)) ||
                !grow(&run->value, capacity, sizeof(double)))
                return MPS2P_ERR_NOMEM;
            run->capacity = capacity;
        }
        size_t column_first = entries;
        for (int m = c->member_start[g]; m < c->member_start[g + 1]; m++) {
            int i = c->member[m];
            for (int k = a->row_start[i]; k < a->row_start[i + 1]; k++) {
                int h = c->aggregate_of[a->column[k]];
                if (h > g || a->value[k] == 0.0) /* ppe_pattern neighbour_list's zeros */
                    continue;
                if (run->marker[h] != g) {
                    run->marker[h] = g;
                    run->row[entries++] = h;
                    run->accumulated[h] = 0.0;
                }
                run->accumulated[h] += a->value[k];
            }
        }
        qsort(run->row + column_first, entries - column_first, sizeof *run->row, compare_int);
        for (size_t e = column_first; e < entries; e++)
            run->value[e] = run->accumulated[run->row[e]];
        c->coarse_start[g + 1] = (int)entries;
    }
    run->entries = entries;
    return MPS2P_OK;
}

/* Runs whose bookkeeping a build keeps on the stack. */
#define STACK_RUNS 8

/* A_c's upper triangle by columns. With threads, each builds a contiguous
 * run of columns, the first straight into A_c, the others into room of
 * their own, copied in behind it (as the neighbour list's runs): every
 * column is built by one thread as with one, the same bits for any team. */
static int build_coarse(coarse_level *c, const sparse_matrix *a, double threads,
                        size_t *entries_out)
{
    size_t runs = a->rows < REDUCTION_BLOCK ? 1 : (size_t)team_size(threads);
    column_run stack_runs[STACK_RUNS];
    int stack_splits[STACK_RUNS + 1];
    column_run *run = runs <= STACK_RUNS ? stack_runs : calloc(runs, sizeof *run);
    int *split = runs <= STACK_RUNS ? stack_splits : calloc(runs + 1, sizeof *split);
    if (!run || !split) { /* one run, as one thread: the same columns */
        if (run != stack_runs)
            free(run);
        if (split != stack_splits)
            free(split);
        run = stack_runs;
        split = stack_splits;
        runs = 1;
    }
    int failed = 0;
    /* runs of about equal numbers of members */
    size_t r = 0;
    for (int g = 0; g <= c->count && r <= runs; g++)
        while (r <= runs && (size_t)c->member_start[g] >= (size_t)a->rows * r / runs)
            split[r++] = g;
    for (; r <= runs; r++)
        split[r] = c->count;
    split[0] = 0;
    split[runs] = c->count;
    run[0] = (column_run){c->coarse_row, c->coarse_value, c->entries_capacity, 0,
                          c->marker, c->accumulated};
    size_t ready = 1; /* runs with their marker and sums */
    for (size_t q = 1; q < runs; q++) {
        run[q] = (column_run){NULL, NULL, 0, 0, malloc((size_t)c->count * sizeof(int)),
                              malloc((size_t)c->count * sizeof(double))};
        ready += run[q].marker && run[q].accumulated;
    }
    if (ready < runs) { /* one run, as one thread: the same columns */
        for (size_t q = 1; q < runs; q++) {
            free(run[q].marker);
            free(run[q].accumulated);
        }
        runs = 1;
        split[1] = c->count;
    }
    PARALLEL_FOR(threads, schedule(static, 1) reduction(| : failed) if (runs > 1),
    for (size_t q = 0; q < runs; q++) {
        failed |= build_columns(c, a, split[q], split[q + 1], &run[q]) != MPS2P_OK;
    });
    c->coarse_row = run[0].row;
    c->coarse_value = run[0].value;
    c->entries_capacity = run[0].capacity;
    size_t total = 0;
    if (!failed) {
        for (size_t q = 0; q < runs; q++)
            total += run[q].entries;
        if (total > c->entries_capacity) {
            failed = !grow(&c->coarse_row, total, sizeof(int)) ||
                     !grow(&c->coarse_value, total, sizeof(double));
            if (!failed)
                c->entries_capacity = total;
        }
    }
    if (!failed) {
        c->coarse_start[0] = 0;
        size_t offset = run[0].entries;
        for (size_t q = 1; q < runs; q++) {
            if (run[q].entries > 0) {
                memcpy(c->coarse_row + offset, run[q].row, run[q].entries * sizeof(int));
                memcpy(c->coarse_value + offset, run[q].value, run[q].entries * sizeof(double));
            }
            for (int g = split[q]; g < split[q + 1]; g++)
                c->coarse_start[g + 1] += (int)offset;
            offset += run[q].entries;
        }
    }
    for (size_t q = 1; q < runs; q++) {
        free(run[q].row);
        free(run[q].value);
        free(run[q].marker);
        free(run[q].accumulated);
    }
    if (run != stack_runs)
        free(run);
    if (split != stack_splits)
        free(split);
    *entries_out = total;
    return failed ? MPS2P_ERR_NOMEM : MPS2P_OK;
}

int coarse_level_setup(coarse_level *c, const sparse_matrix *a, double threads, char *message,
                       size_t size)
{
    const size_t n = (size_t)a->rows;
    if (n > c->rows_capacity) {
        if (!grow(&c->aggregate_of, n, sizeof(int)) || !grow(&c->member, n, sizeof(int)))
            goto out_of_memory;
        c->rows_capacity = n;
    }
    c->rows = a->rows;
    c->count = 0; /* until the factor stands: coarse_level_solve refuses */
    cholmod_free_factor(&c->factor, &c->common);
    const int aggregates = aggregate(a, c->aggregate_of);
    const size_t count = (size_t)aggregates;
    if (count + 1 > c->count_capacity) {
        if (!grow(&c->member_start, count + 1, sizeof(int)) ||
            !grow(&c->lead_order, count + 1, sizeof(int)) ||
            !grow(&c->coarse_start, count + 1, sizeof(int)) ||
            !grow(&c->marker, count + 1, sizeof(int)) ||
            !grow(&c->accumulated, count + 1, sizeof(double)) ||
            !grow(&c->restricted, count + 1, sizeof(double)))
            goto out_of_memory;
        c->count_capacity = count + 1;
    }
    c->count = aggregates;
    group_members(c, a->rows);
    size_t entries = 0;
    if (build_coarse(c, a, threads, &entries) != MPS2P_OK)
        goto out_of_memory;

    cholmod_sparse matrix = {0};
    matrix.nrow = matrix.ncol = count;
    matrix.nzmax = entries;
    matrix.p = c->coarse_start;
    matrix.i = c->coarse_row;
    matrix.x = c->coarse_value;
    matrix.stype = 1;
    matrix.itype = CHOLMOD_INT;
    matrix.xtype = CHOLMOD_REAL;
    matrix.dtype = CHOLMOD_DOUBLE;
    matrix.sorted = 1;
    matrix.packed = 1;
    cholmod_common *cc = &c->common;
    cc->supernodal = count < SUPERNODAL_FROM_ROWS ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO;
    /* the aggregates, and so the pattern, change with the matrix: analyse anew */
    c->factor = cholmod_analyze(&matrix, cc);
    if (c->factor)
        cholmod_factorize(&matrix, c->factor, cc);
    if (!c->factor || cc->status != CHOLMOD_OK || c->factor->minor < c->factor->n) {
        if (cc->status == CHOLMOD_OUT_OF_MEMORY)
            goto out_of_memory;
        snprintf(message, size,
                 "two-level preconditioner: the coarse matrix (%zu aggregates) is not "
                 "positive definite (CHOLMOD status %d)", count, cc->status);
        cholmod_free_factor(&c->factor, cc);
        c->count = 0;
        return MPS2P_ERR_SOLVE;
    }
    return MPS2P_OK;
out_of_memory:
    snprintf(message, size, "out of memory for the two-level preconditioner");
    cholmod_free_factor(&c->factor, &c->common);
    c->count = 0;
    return MPS2P_ERR_NOMEM;
}

/* The first q whose aggregate lead_order[q] starts at or after row. */
static int first_lead_from(const coarse_level *c, size_t row)
{
    int low = 0, high = c->count;
    while (low < high) {
        int middle = low + (high - low) / 2;
        if ((size_t)c->member[c->member_start[c->lead_order[middle]]] < row)
            low = middle + 1;
        else
            high = middle;
    }
    return low;
}

/* Each sum is a chain of dependent additions (about ten): four aggregates at
 * a time, side by side, each still summed in its members' order. */
#define RESTRICT_LANES 4

void coarse_level_restrict(coarse_level *c, const double *r, size_t first_row, size_t end_row)
{
    if (!c->factor)
        return;
    const int first = first_lead_from(c, first_row), end = first_lead_from(c, end_row);
    const int *start = c->member_start, *member = c->member;
    int q = first;
    for (; q + RESTRICT_LANES <= end; q += RESTRICT_LANES) {
        const int *members[RESTRICT_LANES];
        int length[RESTRICT_LANES], common = INT_MAX;
        double sum[RESTRICT_LANES];
        for (int lane = 0; lane < RESTRICT_LANES; lane++) {
            const int g = c->lead_order[q + lane];
            members[lane] = member + start[g];
            length[lane] = start[g + 1] - start[g];
            common = length[lane] < common ? length[lane] : common;
            sum[lane] = 0.0;
        }
        for (int m = 0; m < common; m++)
            for (int lane = 0; lane < RESTRICT_LANES; lane++)
                sum[lane] += r[members[lane][m]];
        for (int lane = 0; lane < RESTRICT_LANES; lane++) {
            for (int m = common; m < length[lane]; m++)
                sum[lane] += r[members[lane][m]];
            c->restricted[c->lead_order[q + lane]] = sum[lane];
        }
    }
    for (; q < end; q++) {
        const int g = c->lead_order[q];
        double sum = 0.0;
        for (int m = start[g]; m < start[g + 1]; m++)
            sum += r[member[m]];
        c->restricted[g] = sum;
    }
}

const double *coarse_level_solve_restricted(coarse_level *c, const int **aggregate_of)
{
    if (!c->factor)
        return NULL; /* no setup, or a failed one */
    cholmod_dense rhs = {0};
    rhs.nrow = rhs.d = rhs.nzmax = (size_t)c->count;
    rhs.ncol = 1;
    rhs.x = c->restricted;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, c->factor, &rhs, NULL, &c->solution, NULL, &c->work_y,
                        &c->work_e, &c->common))
        return NULL;
    *aggregate_of = c->aggregate_of;
    return c->solution->x;
}

const double *coarse_level_solve(coarse_level *c, const double *r, const int **aggregate_of)
{
    coarse_level_restrict(c, r, 0, (size_t)c->rows);
    return coarse_level_solve_restricted(c, aggregate_of);
}

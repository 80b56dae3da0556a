/* Numerics that know no solver: the threads of a particle loop, the MPS
 * kernel and the reference lattice (kernel.c), the neighbour list
 * (neighbours.c), sparse matrices and their solvers (linear_solver.c). */
#ifndef MPS2P_NUMERICS_H
#define MPS2P_NUMERICS_H

#include "mps2p.h" /* status codes */

#include <stddef.h>
#include <stdint.h>
#include <math.h>   /* sqrt, for kernel_weight_squared */
#include <stdlib.h> /* realloc, for grow */
#ifdef _OPENMP
#include <omp.h>
#endif

/* Threads of a parallel loop for a `threads` setting (parameter threads:
 * 0 = OpenMP's default). Given to each loop's num_threads clause, never set
 * process-wide, so two solvers can run with different counts side by side.
 * Inside a parallel region (SIDE_BY_SIDE's, or a host's own) it is 1: the
 * code there takes its one-thread paths, which give the same bits. */
static inline int team_size(double threads)
{
#ifdef _OPENMP
    if (threads == 1.0 || omp_in_parallel()) /* one thread: libgomp is not asked */
        return 1;
    return threads >= 1.0 ? (int)threads : omp_get_max_threads();
#else
    (void)threads;
    return 1;
#endif
}

/* PARALLEL_FOR(threads, clauses, for-statement): the loop over team_size
 * threads with OpenMP's "parallel for" and the given clauses (schedule,
 * reduction, if; no commas). With one thread, or without OpenMP, it is the
 * plain loop: libgomp is never entered, since it exits the process when its
 * own allocations fail (libmps2p returns MPS2P_ERR_NOMEM instead). Each
 * iteration writes only its own outputs, or the clause is an order-free
 * reduction (|, + of integers), so the results do not depend on the team. */
#ifdef _OPENMP
#define OMP_PRAGMA_(...) _Pragma(#__VA_ARGS__)
#define PARALLEL_FOR(threads, clauses, ...)                                      \
    do {                                                                         \
        const int team_ = team_size(threads);                                    \
        if (team_ > 1) {                                                         \
            OMP_PRAGMA_(omp parallel for num_threads(team_) clauses)             \
            __VA_ARGS__                                                          \
        } else {                                                                 \
            __VA_ARGS__                                                          \
        }                                                                        \
    } while (0)
#else
#define PARALLEL_FOR(threads, clauses, ...)                                      \
    do {                                                                         \
        (void)(threads);                                                         \
        __VA_ARGS__                                                              \
    } while (0)
#endif

/* The schedule clause of a particle loop whose rows cost unequal work (a
 * fluid particle's row beside a wall's, which the loop skips; a scene lists
 * its walls last, so equal shares of rows were unequal shares of work):
 * chunks of rows handed to the threads as they come free. Each row writes
 * only its own outputs, so the results do not depend on it. */
#define UNEQUAL_ROWS schedule(dynamic, 64)

/* SIDE_BY_SIDE(threads, first, second): the two statements at once, each on
 * one thread, when team_size(threads) > 1; else first, then second. first
 * runs on the calling thread, so the per-thread error message it may set
 * (fail) is the caller's; second must not fail. They must not write what the
 * other reads or writes; each then computes what it computes alone, so the
 * results do not depend on the team. */
#ifdef _OPENMP
#define SIDE_BY_SIDE(threads, first, second)                                     \
    do {                                                                         \
        if (team_size(threads) > 1) {                                            \
            OMP_PRAGMA_(omp parallel num_threads(2))                             \
            {                                                                    \
                /* a team of one (OpenMP may give fewer): both, in turn */   \
                if (omp_get_thread_num() == 0) {                                 \
                    first;                                                       \
                }                                                                \
                if (omp_get_thread_num() == 1 || omp_get_num_threads() == 1) {   \
                    second;                                                      \
                }                                                                \
            }                                                                    \
        } else {                                                                 \
            first;                                                               \
            second;                                                              \
        }                                                                        \
    } while (0)
#else
#define SIDE_BY_SIDE(threads, first, second)                                     \
    do {                                                                         \
        (void)(threads);                                                         \
        first;                                                                   \
        second;                                                                  \
    } while (0)
#endif

/* Reductions (sums, maxima) are taken over fixed blocks of this many
 * particles or unknowns, each summed in order, and the block results
 * combined in block order: the same bits for any number of threads. */
#define REDUCTION_BLOCK 1024

/* ---- kernel and reference lattice (kernel.c) ---- */

static inline double kernel_weight(double r, double re)
{
    return (r > 0.0 && r < re) ? re / r - 1.0 : 0.0;
}

/* kernel_weight(sqrt(r2), re), the same bits, with the square root and the
 * division only inside a bound a hair over re^2 (the rows reach re plus the
 * list's skin: a quarter of their pairs are beyond re). */
static inline double kernel_weight_squared(double r2, double re)
{
    return r2 < re * re * (1.0 + 1e-12) ? kernel_weight(sqrt(r2), re) : 0.0;
}

/* n0 and lambda of an interior particle of the square lattice of spacing l0. */
void lattice_constants(double l0, double re, double *n0, double *lambda);

/* ---- neighbour list (neighbours.c) ---- */

/* Where a team's pair blocks split, as shares of the rows' entries, moved
 * after each call toward equal times (pair_blocks.c): entries do not all
 * cost the same (a moving liquid's neighbours lie scattered in memory, a
 * wall's in order; viscosity skips the walls' pairs), and equal entries left
 * one thread waiting a third of a block's time in the paper's case
 * (docs/performance.md); the neighbour list's runs split the same way.
 * Results do not depend on the split. One for each pair sum of a solver
 * (not shared: two solvers in two threads). */
#define BALANCED_BLOCKS 8
typedef struct pair_balance {
    double share[BALANCED_BLOCKS + 1]; /* block b starts at share[b] of the entries */
    double seconds[BALANCED_BLOCKS];   /* each block's time in the last call */
    size_t blocks;                     /* the team the shares are for (0: none yet) */
} pair_balance;

/* The block's first row: where share of the entries lie before it. */
size_t pair_balance_first(const pair_balance *balance, const size_t *start, size_t count,
                          size_t b);
/* Shares for a team of blocks (equal entries) unless they are for it. */
void pair_balance_prepare(pair_balance *balance, size_t blocks);
/* Moves the shares toward equal times after a call. */
void pair_balance_update(pair_balance *balance);
double pair_balance_clock(void);

/* Every pair closer than cutoff = max radius + skin, kept as a compressed
 * row list (both directions, ordered by index); rebuilt when a row lacks a
 * pair now within cutoff - skin (needs_rebuild), so each stage can reuse it.
 * At each build a short list is also taken from it: the pairs closer than
 * short_radius + skin (short_radius = re_density l0), in the same order, for
 * the stages that look no further than short_radius (about 20 neighbours
 * instead of 60); see neighbour_rows_within. */
typedef struct neighbour_list {
    double cutoff, skin;
    size_t count;
    size_t *start;       /* count + 1 */
    uint32_t *index;     /* start[count] entries (4-byte particle indices: see
                          * neighbours_init) */
    size_t capacity;
    double short_radius; /* 0 = no short list (it would be the long one) */
    size_t *short_start; /* count + 1, NULL without a short list */
    uint32_t *short_index; /* short_start[count] entries */
    size_t short_capacity;
    double *built_at;    /* positions at the last build, 2 * count */
    /* cell grid over the domain */
    double origin[2];
    double cell_size;
    size_t cells[2];
    uint32_t *cell_start;  /* cells + 1 */
    uint32_t *cell_cursor; /* cells, fill position while sorting */
    uint32_t *cell_particle;
    unsigned long builds;
    int stale;           /* a rebuild failed half-way: rebuild at the next update */
    double threads;      /* parameter threads (team_size) */
    pair_balance runs_balance; /* where a build's runs split (pair_balance) */
    /* Particles left out of every pair (an empty row, in no other row):
     * those i with skip[i] == skip_value; skip NULL = none. Read at each
     * build: the solver points it at its kinds, so that fluid out of the run
     * is nobody's neighbour, and rebuilds when one leaves. */
    const int *skip;
    int skip_value;
} neighbour_list;

/* short_radius: the radius the short list must serve (re_density l0); 0, or
 * one within skin of cutoff, keeps no short list. */
int neighbours_init(neighbour_list *list, size_t count, double cutoff, double skin,
                    double short_radius, const double domain[4]);
void neighbours_free(neighbour_list *list);
/* Rebuilds both lists when needed; returns MPS2P_OK or MPS2P_ERR_NOMEM (both
 * lists then empty and stale, rebuilt at the next update). */
int neighbours_update(neighbour_list *list, const double *position);
/* Builds the lists now, whether needed or not (after a change of the
 * particles left out); the same return and failure as neighbours_update. */
int neighbours_rebuild(neighbour_list *list, const double *position);
/* Builds the list from the positions of an earlier build (built_at) and sets
 * the build count, so that a restored solver reuses the same pairs and makes
 * the same rebuild decisions as the one it was saved from. built_at must not
 * be list->built_at itself (it is copied there). */
int neighbours_restore(neighbour_list *list, const double *built_at, unsigned long builds);

/* The rows a stage loops over for the pairs closer than radius: the short
 * list when radius is within its radius, else the long one. The short list
 * holds, in the same order, every pair of the long one closer than
 * short_radius + skin at the build, so a stage that skips the pairs at radius
 * or beyond sees the same pairs, in the same order, from either: its sums
 * come out bit for bit the same. */
typedef struct neighbour_rows {
    const size_t *start;
    const uint32_t *index;
} neighbour_rows;

static inline neighbour_rows neighbour_rows_within(const neighbour_list *list, double radius)
{
    neighbour_rows rows = {list->start, list->index};
    if (list->short_start && radius <= list->short_radius) {
        rows.start = list->short_start;
        rows.index = list->short_index;
    }
    return rows;
}

/* Row i's first entry above i. With one thread, a pair sum over the rows
 * can take each pair once, in the row of its lower index, and add its term
 * to both rows: since the rows are done in index order and each row is
 * sorted, row j still receives its terms in ascending order of neighbour
 * (those below j from the rows before it, then its own from here on), the
 * order the row-by-row loop adds them in, so the sums are the same bits at
 * half the pair weights. (r_ji = -r_ij exactly in floating point: both
 * rows see the same distance.) */
static inline size_t first_above(neighbour_rows rows, size_t i)
{
    size_t k = rows.start[i], end = rows.start[i + 1];
    while (k < end && rows.index[k] < i)
        k++;
    return k;
}

/* The first row i of count with start[i] >= target. */
static inline size_t first_row_from(const size_t *start, size_t count, size_t target)
{
    size_t low = 0, high = count;
    while (low < high) {
        size_t middle = low + (high - low) / 2;
        if (start[middle] < target)
            low = middle + 1;
        else
            high = middle;
    }
    return low;
}

/* With threads, the pair sums above run in blocks of consecutive rows, one
 * block a thread: a block first gives each of its rows, in ascending order,
 * the terms of its neighbours below the block (pair_block_first), then takes
 * each pair inside it or above it once, from its lower row, adding the term
 * to the upper row only when that row is in the block (below the block's end;
 * the upper block takes it in its first pass). Every row still sums its
 * terms in ascending order of neighbour: the same bits for any number of
 * blocks and wherever they split, and one block is the one-thread loop.
 * Block b of count rows starts where b / blocks of the rows' entries (start,
 * the rows' offsets) lie before it: blocks of equal work, not of equal rows
 * (walls' dummies have empty rows, and a scene lists them last). */
static inline size_t pair_block_first(const size_t *start, size_t count, size_t blocks,
                                      size_t b)
{
    if (b >= blocks)
        return count;
    return first_row_from(start, count,
                          start[0] + (start[count] - start[0]) / blocks * b +
                              (start[count] - start[0]) % blocks * b / blocks);
}

/* PAIR_BLOCKS(threads, start, count, balance, first, end, body): body once
 * for each block of rows [first, end) of count (start: the rows' offsets),
 * one block a thread of team_size(threads), split where balance says. */
#define PAIR_BLOCKS(threads, start, count, balance, first, end, ...)                \
    do {                                                                         \
        const size_t blocks_ = (size_t)team_size(threads);                       \
        pair_balance *const balance_ =                                           \
            blocks_ > 1 && blocks_ <= BALANCED_BLOCKS ? (balance) : NULL;        \
        if (balance_)                                                            \
            pair_balance_prepare(balance_, blocks_);                             \
        PARALLEL_FOR(threads, schedule(static, 1) if (blocks_ > 1),              \
        for (size_t block_ = 0; block_ < blocks_; block_++) {                    \
            const size_t first = balance_ ? pair_balance_first(balance_, start, count, block_) \
                                          : pair_block_first(start, count, blocks_, block_); \
            const size_t end = balance_ ? pair_balance_first(balance_, start, count, block_ + 1) \
                                        : pair_block_first(start, count, blocks_, block_ + 1); \
            const double began_ = balance_ ? pair_balance_clock() : 0.0;         \
            __VA_ARGS__                                                          \
            if (balance_)                                                        \
                balance_->seconds[block_] = pair_balance_clock() - began_;       \
        });                                                                      \
        if (balance_)                                                            \
            pair_balance_update(balance_);                                       \
    } while (0)

/* The end of row i's entries below limit (a block's end): the entries from
 * there on belong to rows another block sums. */
static inline size_t row_end_below(neighbour_rows rows, size_t i, size_t limit)
{
    size_t k = rows.start[i + 1], first = rows.start[i];
    while (k > first && rows.index[k - 1] >= limit)
        k--;
    return k;
}

/* ---- linear solvers (linear_solver.c) ---- */

/* GAMG: PETSc's CG with algebraic multigrid, only with option petsc
 * (gamg_solver.c; MPS2P_HAVE_PETSC). */
enum pressure_solver_kind {
    PRESSURE_SOLVER_CHOLMOD = 0,
    PRESSURE_SOLVER_CG = 1,
    PRESSURE_SOLVER_GAMG = 2
};
enum cg_preconditioner_kind {
    CG_PRECONDITIONER_JACOBI = 0,
    CG_PRECONDITIONER_IC0 = 1,
    CG_PRECONDITIONER_TWO_LEVEL = 2
};

/* A symmetric matrix in compressed rows, full pattern (both triangles). */
typedef struct sparse_matrix {
    int rows;
    int *row_start;      /* rows + 1; int, as CHOLMOD's int interface wants */
    int *column;
    double *value;
    size_t capacity;     /* of column and value */
    size_t row_capacity; /* of row_start */
} sparse_matrix;

typedef struct linear_solver linear_solver;

/* Grows *array (a pointer to any element type) to hold count elements of
 * size bytes; 0, the array untouched, when it cannot. */
static inline int grow(void *array, size_t count, size_t size)
{
    void *grown = realloc(*(void **)array, count * size);
    if (!grown)
        return 0;
    *(void **)array = grown;
    return 1;
}

/* The coarse level of CG's two-level preconditioner (coarse_level.c). */
typedef struct coarse_level coarse_level;
int coarse_level_create(coarse_level **out, char *message, size_t size);
void coarse_level_destroy(coarse_level *c);
size_t coarse_level_memory(const coarse_level *c);
/* Aggregates of A's unknowns, A_c = P^T A P factorised. */
int coarse_level_setup(coarse_level *c, const sparse_matrix *a, double threads, char *message,
                       size_t size);
/* A_c^-1 P^T r, one value an aggregate, and the aggregate of each unknown;
 * NULL without a factor (no setup, or a failed one) or when CHOLMOD's solve
 * fails (out of memory). */
const double *coarse_level_solve(coarse_level *c, const double *r, const int **aggregate_of);
/* coarse_level_solve in two parts, for a team: P^T r for the aggregates whose
 * first unknown is in rows [first_row, end_row) (each summed over its
 * unknowns in order: the same bits as one pass), then the solve, once all
 * aggregates are restricted. */
void coarse_level_restrict(coarse_level *c, const double *r, size_t first_row, size_t end_row);
const double *coarse_level_solve_restricted(coarse_level *c, const int **aggregate_of);

/* kind: enum pressure_solver_kind; preconditioner: enum cg_preconditioner_kind
 * (CG only); threads: parameter threads, for CG's loops (team_size). Fails
 * with a message: MPS2P_ERR_NOMEM, or MPS2P_ERR_INVALID for gamg in a build
 * without PETSc. */
int linear_solver_create(int kind, int preconditioner, double threads,
                         linear_solver **solver, char *message, size_t size);
void linear_solver_destroy(linear_solver *solver);
/* Solves A x = b; x holds the initial guess on entry (used by CG). */
/* CHOLMOD symbolic analyses so far (a matrix of the last one's pattern reuses it). */
uint64_t linear_solver_analyses(const linear_solver *solver);
/* Bytes of workspace, CHOLMOD's included. */
size_t linear_solver_memory(const linear_solver *solver);
int linear_solver_solve(linear_solver *solver, const sparse_matrix *a,
                        const double *b, double *x, double tolerance,
                        size_t max_iterations, size_t *iterations,
                        double *residual, char *message, size_t size);

/* 1 when this build has pressure_solver gamg (option petsc). */
int linear_solver_have_gamg(void);

/* ---- GAMG (gamg_solver.c, only with MPS2P_HAVE_PETSC) ---- */

typedef struct gamg_solver gamg_solver;
int gamg_create(gamg_solver **solver, char *message, size_t size);
void gamg_destroy(gamg_solver *solver);
/* Bytes it holds, with an estimate of the last solve's multigrid hierarchy. */
size_t gamg_memory(const gamg_solver *solver);
/* CG + GAMG from the initial guess x to |b - A x| <= tolerance |b|. */
int gamg_solve(gamg_solver *solver, const sparse_matrix *a, const double *b, double *x,
               double tolerance, size_t max_iterations, size_t *iterations, char *message,
               size_t size);

#endif

/* Cell-linked list and a Verlet neighbour list reused by every stage, with
 * a short list of the pairs within the density radius taken from it.
 * Particle indices are stored in 4 bytes (half the memory of size_t; the
 * lists are the solver's largest arrays) and a build marks a short-list pair
 * in an index's low bit (2 j + 1): the particle limit of scenes and
 * checkpoints, MAX_PARTICLES (core.h, which asserts it), keeps both below
 * 2^32. */
#include "numerics/numerics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Keeps the grid small when the domain is huge compared with the cutoff. */
#define MAX_CELLS_PER_PARTICLE 4
#define MIN_CELL_BUDGET 65536

int neighbours_init(neighbour_list *list, size_t count, double cutoff, double skin,
                    double short_radius, const double domain[4])
{
    memset(list, 0, sizeof *list);
    list->count = count;
    list->cutoff = cutoff;
    list->skin = skin;
    /* a short list as long as the long one would only cost its copy */
    if (short_radius > 0.0 && short_radius + skin < cutoff)
        list->short_radius = short_radius;
    list->origin[0] = domain[0];
    list->origin[1] = domain[1];
    double width = domain[2] - domain[0], height = domain[3] - domain[1];
    double budget = fmax((double)MIN_CELL_BUDGET, (double)MAX_CELLS_PER_PARTICLE * count);
    double cell = cutoff;
    /* Cells of at least sqrt(area / budget) and of each side / budget: at
     * most about 3 budget cells, however long and thin the domain (the area
     * bound alone let a thin domain have more cells along it than a size_t
     * holds). The callers make width and height finite. */
    if ((width / cell + 1) * (height / cell + 1) > budget)
        cell = fmax(sqrt(width * height / budget), fmax(width, height) / budget) * 1.01 + cutoff;
    list->cell_size = cell;
    list->cells[0] = (size_t)(width / cell) + 1;
    list->cells[1] = (size_t)(height / cell) + 1;
    size_t cells = list->cells[0] * list->cells[1];
    list->start = calloc(count + 1, sizeof *list->start);
    list->built_at = malloc(2 * count * sizeof *list->built_at);
    list->cell_start = malloc((cells + 1) * sizeof *list->cell_start);
    list->cell_cursor = malloc(cells * sizeof *list->cell_cursor);
    list->cell_particle = malloc(count * sizeof *list->cell_particle);
    if (list->short_radius > 0.0)
        list->short_start = calloc(count + 1, sizeof *list->short_start);
    if (!list->start || !list->built_at || !list->cell_start || !list->cell_cursor ||
        !list->cell_particle ||
        (list->short_radius > 0.0 && !list->short_start)) {
        neighbours_free(list);
        return MPS2P_ERR_NOMEM;
    }
    return MPS2P_OK;
}

void neighbours_free(neighbour_list *list)
{
    free(list->start);
    free(list->index);
    free(list->built_at);
    free(list->cell_start);
    free(list->cell_cursor);
    free(list->cell_particle);
    free(list->short_start);
    free(list->short_index);
    memset(list, 0, sizeof *list);
}

static size_t cell_coordinate(double x, double origin, double size, size_t cells)
{
    double c = floor((x - origin) / size);
    if (!(c >= 0.0)) /* also catches NaN */
        return 0;
    if (c >= (double)cells)
        return cells - 1;
    return (size_t)c;
}

/* The cell particle i is in: computed again where needed rather than stored
 * (8 bytes a particle); the same positions give the same cell. */
static size_t cell_of(const neighbour_list *list, const double *position, size_t i)
{
    size_t cx = cell_coordinate(position[2 * i], list->origin[0], list->cell_size,
                                list->cells[0]);
    size_t cy = cell_coordinate(position[2 * i + 1], list->origin[1], list->cell_size,
                                list->cells[1]);
    return cy * list->cells[0] + cx;
}

/* Particle i's squared displacement since the last build. */
static double moved2(const neighbour_list *list, const double *position, size_t i)
{
    double dx = position[2 * i] - list->built_at[2 * i];
    double dy = position[2 * i + 1] - list->built_at[2 * i + 1];
    return dx * dx + dy * dy;
}

static int skipped(const neighbour_list *list, size_t i)
{
    return list->skip && list->skip[i] == list->skip_value;
}

/* Whether j is in the sorted row index[first, end) (asked rarely: the
 * pairs that moved apart by more than the skin and are within reach). */
static int listed(const uint32_t *index, size_t first, size_t end, size_t j)
{
    for (size_t k = first; k < end && index[k] <= j; k++)
        if (index[k] == j)
            return 1;
    return 0;
}

/* Whether the row of particle i (moved by more than half the skin, at most
 * the skin, since the last build) lacks a particle now within the stages'
 * largest radius (cutoff - skin) or, for the short row, within short_radius.
 * A pair beyond the cutoff at the build can be within cutoff - skin now only
 * if the difference of its two displacements is longer than the skin; its
 * other particle was then within the cutoff of i's place now: in the 3x3
 * cells (each at least the cutoff wide) around it. */
static int row_lacks_pair(const neighbour_list *list, const double *position, size_t i)
{
    /* a hair's margin each way, so that rounding can only rebuild more */
    const double wider = 1.0 + 1e-9, reach = list->cutoff - list->skin;
    const double reach2 = reach * reach * wider;
    const double short_reach2 =
        list->short_start ? list->short_radius * list->short_radius * wider : 0.0;
    const double skin2 = list->skin * list->skin / wider;
    const double xi = position[2 * i], yi = position[2 * i + 1];
    const double moved_x = xi - list->built_at[2 * i], moved_y = yi - list->built_at[2 * i + 1];
    size_t c = cell_of(list, position, i), columns = list->cells[0];
    size_t cx = c % columns, cy = c / columns;
    size_t x0 = cx > 0 ? cx - 1 : 0, x1 = cx + 1 < columns ? cx + 1 : cx;
    size_t y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < list->cells[1] ? cy + 1 : cy;
    for (size_t y = y0; y <= y1; y++) {
        for (size_t k = list->cell_start[y * columns + x0];
             k < list->cell_start[y * columns + x1 + 1]; k++) {
            size_t j = list->cell_particle[k];
            /* the rare test first: most of a row's neighbourhood moves with it */
            double apart_x = moved_x - (position[2 * j] - list->built_at[2 * j]);
            double apart_y = moved_y - (position[2 * j + 1] - list->built_at[2 * j + 1]);
            if (apart_x * apart_x + apart_y * apart_y <= skin2)
                continue;
            double dx = position[2 * j] - xi, dy = position[2 * j + 1] - yi;
            double d2 = dx * dx + dy * dy;
            if (!(d2 < reach2))
                continue;
            if (!listed(list->index, list->start[i], list->start[i + 1], j) ||
                (d2 < short_reach2 &&
                 !listed(list->short_index, list->short_start[i], list->short_start[i + 1], j)))
                return 1;
        }
    }
    return 0;
}

/* A pair can have closed in since the last build by at most the sum of its
 * two particles' displacements, so the rows hold every pair within cutoff -
 * skin while no two displacements add up to more than the skin. Past that,
 * rather than rebuilding at once (the paper's case did for a jet moving as
 * one, or for two spray particles far apart: 949 builds in 1845 steps, 595
 * now, docs/performance.md), the rows of the particles moved by more than
 * half the skin are compared with their neighbourhoods now; the list is
 * rebuilt when one lacks a pair, or when a particle has moved by more than
 * the skin (its neighbourhood is then beyond the cells searched). A row's
 * pairs beyond a stage's radius add nothing to its sums: the results do not
 * depend on when the list was built (but for option ppe_pattern
 * "neighbour_list", whose matrix holds them: by rounding). Maxima and ORs:
 * the same for any split among threads. */
static int needs_rebuild(const neighbour_list *list, const double *position)
{
    if (list->builds == 0 || list->stale)
        return 1;
    const double skin2 = list->skin * list->skin;
    double largest = 0.0;
    int not_finite = 0;
    PARALLEL_FOR(list->threads, schedule(static) reduction(max : largest) reduction(| : not_finite),
    for (size_t i = 0; i < list->count; i++) {
        double d2 = moved2(list, position, i);
        not_finite |= !isfinite(d2);
        largest = d2 > largest ? d2 : largest;
    });
    if (not_finite || largest > skin2)
        return 1;
    if (4.0 * largest <= skin2)
        return 0; /* twice the largest is within the skin */
    int lacking = 0;
    PARALLEL_FOR(list->threads, schedule(dynamic, 64) reduction(| : lacking),
    for (size_t i = 0; i < list->count; i++) {
        double d2 = moved2(list, position, i);
        if (!lacking && 4.0 * d2 > skin2 && !skipped(list, i))
            lacking = row_lacks_pair(list, position, i);
    });
    return lacking;
}

/* Counting sort of particles into cells; particles keep index order inside a
 * cell, so the lists come out the same on every run. Skipped particles are
 * in no cell, so no row finds them. */
static void sort_into_cells(neighbour_list *list, const double *position)
{
    size_t cells = list->cells[0] * list->cells[1];
    memset(list->cell_start, 0, (cells + 1) * sizeof *list->cell_start);
    for (size_t i = 0; i < list->count; i++)
        if (!skipped(list, i))
            list->cell_start[cell_of(list, position, i) + 1]++;
    for (size_t c = 0; c < cells; c++)
        list->cell_start[c + 1] += list->cell_start[c];
    memcpy(list->cell_cursor, list->cell_start, cells * sizeof *list->cell_cursor);
    for (size_t i = 0; i < list->count; i++)
        if (!skipped(list, i))
            list->cell_particle[list->cell_cursor[cell_of(list, position, i)]++] = (uint32_t)i;
}

/* Entries taken from one cell at a time before merging (a cell's pairs are
 * merged in chunks of this size when it holds more). */
#define MERGE_CHUNK 128

/* Merges the sorted run in[0..r) into the sorted row out[0..m), from the back,
 * so that out[0..m+r) is sorted; returns m + r. */
static size_t merge_into(uint32_t *out, size_t m, const uint32_t *in, size_t r)
{
    if (m == 0 || out[m - 1] < in[0]) { /* the runs do not overlap: append */
        memcpy(out + m, in, r * sizeof *in);
        return m + r;
    }
    size_t a = m, b = r, w = m + r;
    while (b > 0) {
        if (a > 0 && out[a - 1] > in[b - 1])
            out[--w] = out[--a];
        else
            out[--w] = in[--b];
    }
    return m + r;
}

/* Visits the 3x3 cells around particle i and stores in out its neighbours
 * closer than cutoff, sorted by index (room for candidates() of them);
 * *near gets how many of them are closer than short_radius + skin, which
 * are also stored, in the same order, in short_out (with a short list).
 * Rows must be sorted by index: the stages sum over them in that order, and
 * the order fixes the bits of every sum. A cell lists its particles in index
 * order (sort_into_cells), so each cell gives a sorted run, and the row is
 * the merge of those runs: no general sort. */
static size_t gather(const neighbour_list *list, const double *position, size_t i,
                     uint32_t *out, uint32_t *short_out, size_t *near)
{
    if (skipped(list, i)) { /* an empty row */
        if (near)
            *near = 0;
        return 0;
    }
    double cut2 = list->cutoff * list->cutoff;
    const int with_short = list->short_start != NULL;
    const double short_cut = list->short_radius + list->skin;
    const double short_cut2 = with_short ? short_cut * short_cut : 0.0;
    const double xi = position[2 * i], yi = position[2 * i + 1];
    size_t c = cell_of(list, position, i);
    long cx = (long)(c % list->cells[0]), cy = (long)(c / list->cells[0]);
    long x0 = cx > 0 ? cx - 1 : 0;
    long x1 = cx + 1 < (long)list->cells[0] ? cx + 1 : cx;
    size_t found = 0, found_near = 0;
    uint32_t run[MERGE_CHUNK];
    for (long y = cy - 1; y <= cy + 1; y++) {
        if (y < 0 || y >= (long)list->cells[1])
            continue;
        size_t row_cell = (size_t)y * list->cells[0];
        for (long x = x0; x <= x1; x++) {
            size_t cell = row_cell + (size_t)x;
            size_t k = list->cell_start[cell], end = list->cell_start[cell + 1];
            while (k < end) {
                size_t taken = 0;
                /* Without a branch: about a third of the candidates are
                 * taken, in no pattern the branch predictor could learn;
                 * each is written to the next slot, which only a taken one
                 * keeps. */
                for (; k < end && taken < MERGE_CHUNK; k++) {
                    size_t j = list->cell_particle[k];
                    double dx = position[2 * j] - xi, dy = position[2 * j + 1] - yi;
                    double d2 = dx * dx + dy * dy;
                    size_t in = (size_t)(d2 < cut2) & (size_t)(j != i);
                    size_t is_near = (size_t)(d2 < short_cut2);
                    /* with a short list, the low bit marks its pairs until split */
                    run[taken] = (uint32_t)(with_short ? 2 * j + is_near : j);
                    taken += in;
                    found_near += in & is_near;
                }
                if (taken > 0)
                    found = merge_into(out, found, run, taken);
            }
        }
    }
    if (with_short) {
        /* Without a branch (about a third are near, in no pattern): a far
         * pair is written to the next near one's slot, or past the row's last
         * near one into sink; never into the next row, which another thread
         * may be filling. */
        size_t stored = 0;
        uint32_t sink;
        for (size_t k = 0; k < found; k++) {
            uint32_t j = out[k] / 2;
            *(stored < found_near ? short_out + stored : &sink) = j;
            stored += out[k] % 2;
            out[k] = j;
        }
    }
    if (near)
        *near = found_near;
    return found;
}

/* Grows an index array to hold total entries; 0 when it cannot. */
static int reserve(uint32_t **index, size_t *capacity, size_t total)
{
    if (total <= *capacity)
        return 1;
    /* a sixteenth to spare: the lists are the solver's largest arrays, and
     * realloc grows a large block in place or by remapping its pages */
    size_t grown_capacity = total + total / 16 + 16;
    uint32_t *grown = realloc(*index, grown_capacity * sizeof *grown);
    if (!grown)
        return 0;
    *index = grown;
    *capacity = grown_capacity;
    return 1;
}

/* Empty, consistent lists after a failed growth: start[] already counts the
 * new pairs that index[] cannot hold. They are rebuilt at the next update
 * even if the particles are back where the last build saw them (a failed
 * step restores them). */
static int fail_growth(neighbour_list *list)
{
    memset(list->start, 0, (list->count + 1) * sizeof *list->start);
    if (list->short_start)
        memset(list->short_start, 0, (list->count + 1) * sizeof *list->short_start);
    list->stale = 1;
    return MPS2P_ERR_NOMEM;
}

/* Particles in the 3x3 cells around particle i, itself not counted: a bound
 * on its row. */
static size_t candidates(const neighbour_list *list, const double *position, size_t i)
{
    if (skipped(list, i))
        return 0;
    size_t c = cell_of(list, position, i), columns = list->cells[0];
    size_t cx = c % columns, cy = c / columns;
    size_t x0 = cx > 0 ? cx - 1 : 0, x1 = cx + 1 < columns ? cx + 1 : cx;
    size_t y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < list->cells[1] ? cy + 1 : cy;
    size_t total = 0;
    for (size_t y = y0; y <= y1; y++)
        total += list->cell_start[y * columns + x1 + 1] - list->cell_start[y * columns + x0];
    return total - 1; /* i is in its own cell */
}

/* Runs whose bookkeeping a build keeps on the stack (build_in_runs). */
#define STACK_RUNS 64

/* Where a run of rows is stored: the index arrays, their room, and how many
 * entries they hold. */
typedef struct row_store {
    uint32_t *index, *short_index;
    size_t capacity, short_capacity, total, short_total;
} row_store;

/* Rows [first, end) stored one after another into store from its start,
 * room made from the bound of each row's candidates (no counting pass);
 * start[i + 1] (and short_start) get the running totals within the run. */
static int store_rows(neighbour_list *list, const double *position, size_t first, size_t end,
                      row_store *store)
{
    const int with_short = list->short_start != NULL;
    store->total = store->short_total = 0;
    for (size_t i = first; i < end; i++) {
        size_t bound = candidates(list, position, i);
        if (bound == 0) { /* an empty row (skipped, or alone): nothing to store */
            list->start[i + 1] = store->total;
            if (with_short)
                list->short_start[i + 1] = store->short_total;
            continue;
        }
        /* the short index keeps one spare slot, so it is never NULL */
        if (!reserve(&store->index, &store->capacity, store->total + bound) ||
            (with_short && !reserve(&store->short_index, &store->short_capacity,
                                    store->short_total + bound + 1)))
            return MPS2P_ERR_NOMEM;
        size_t near = 0;
        store->total += gather(list, position, i, store->index + store->total,
                               with_short ? store->short_index + store->short_total : NULL,
                               &near);
        store->short_total += near;
        list->start[i + 1] = store->total;
        if (with_short)
            list->short_start[i + 1] = store->short_total;
    }
    return MPS2P_OK;
}

/* Each thread stores a contiguous run of rows in one pass: the first run
 * straight into the list, the others into stores of their own, copied in
 * behind it once every run's length is known. Every row is gathered once,
 * by one thread, as with one thread: the lists do not depend on the number
 * of threads. The later runs' stores hold their rows only until copied. */
static int build_in_runs(neighbour_list *list, const double *position)
{
    const int with_short = list->short_start != NULL;
    const size_t n = list->count, runs = (size_t)team_size(list->threads);
    /* the runs' bookkeeping on the stack up to STACK_RUNS threads: a build
     * then allocates nothing but the lists' own room */
    row_store stack_store[STACK_RUNS];
    size_t stack_offset[2 * STACK_RUNS];
    row_store *store = runs <= STACK_RUNS ? stack_store : calloc(runs, sizeof *store);
    size_t *offset = runs <= STACK_RUNS ? stack_offset : calloc(2 * runs, sizeof *offset);
    if (!store || !offset) {
        if (store != stack_store)
            free(store);
        if (offset != stack_offset)
            free(offset);
        return fail_growth(list);
    }
    size_t *short_offset = offset + runs;
    for (size_t run = 1; run < runs; run++)
        store[run] = (row_store){NULL, NULL, 0, 0, 0, 0};
    store[0] = (row_store){list->index, list->short_index, list->capacity,
                           list->short_capacity, 0, 0};
    /* Runs of about equal work: split where the last build's rows (start,
     * still the last build's here) reach the shares of its entries that
     * equalled the last build's times (pair_balance), or equal shares of the
     * rows before a first build. The lists do not depend on the split. */
    size_t stack_split[STACK_RUNS + 1];
    size_t *split = runs <= STACK_RUNS ? stack_split : calloc(runs + 1, sizeof *split);
    if (!split) {
        if (store != stack_store)
            free(store);
        if (offset != stack_offset)
            free(offset);
        return fail_growth(list);
    }
    pair_balance *balance =
        runs > 1 && runs <= BALANCED_BLOCKS && list->start[n] > 0 ? &list->runs_balance : NULL;
    if (balance)
        pair_balance_prepare(balance, runs);
    for (size_t run = 0; run <= runs; run++)
        split[run] = balance              ? pair_balance_first(balance, list->start, n, run)
                     : list->start[n] > 0 ? pair_block_first(list->start, n, runs, run)
                                          : n * run / runs;
    list->start[0] = 0;
    if (with_short)
        list->short_start[0] = 0;
    int failed = 0;
    PARALLEL_FOR(list->threads, schedule(static, 1) reduction(| : failed),
    for (size_t run = 0; run < runs; run++) {
        const double began = balance ? pair_balance_clock() : 0.0;
        failed |= store_rows(list, position, split[run], split[run + 1], &store[run]) !=
                  MPS2P_OK;
        if (balance)
            balance->seconds[run] = pair_balance_clock() - began;
    });
    if (balance && !failed)
        pair_balance_update(balance);
    list->index = store[0].index;
    list->short_index = store[0].short_index;
    list->capacity = store[0].capacity;
    list->short_capacity = store[0].short_capacity;
    size_t total = 0, short_total = 0;
    for (size_t run = 0; run < runs; run++) {
        offset[run] = total;
        short_offset[run] = short_total;
        total += store[run].total;
        short_total += store[run].short_total;
    }
    /* the short index: one spare slot, so never NULL */
    failed = failed || !reserve(&list->index, &list->capacity, total) ||
             (with_short && !reserve(&list->short_index, &list->short_capacity, short_total + 1));
    if (!failed) {
        PARALLEL_FOR(list->threads, schedule(static, 1),
        for (size_t run = 1; run < runs; run++) {
            if (store[run].total > 0)
                memcpy(list->index + offset[run], store[run].index,
                       store[run].total * sizeof *list->index);
            if (with_short && store[run].short_total > 0)
                memcpy(list->short_index + short_offset[run], store[run].short_index,
                       store[run].short_total * sizeof *list->short_index);
            for (size_t i = split[run]; i < split[run + 1]; i++) {
                list->start[i + 1] += offset[run];
                if (with_short)
                    list->short_start[i + 1] += short_offset[run];
            }
        });
    }
    for (size_t run = 1; run < runs; run++) {
        free(store[run].index);
        free(store[run].short_index);
    }
    if (store != stack_store)
        free(store);
    if (offset != stack_offset)
        free(offset);
    if (split != stack_split)
        free(split);
    return failed ? fail_growth(list) : MPS2P_OK;
}

int neighbours_update(neighbour_list *list, const double *position)
{
    if (!needs_rebuild(list, position))
        return MPS2P_OK;
    sort_into_cells(list, position);
    int status = build_in_runs(list, position);
    if (status != MPS2P_OK)
        return status;
    memcpy(list->built_at, position, 2 * list->count * sizeof *position);
    list->builds++;
    list->stale = 0;
    return MPS2P_OK;
}

int neighbours_rebuild(neighbour_list *list, const double *position)
{
    list->stale = 1; /* forces the build */
    return neighbours_update(list, position);
}

int neighbours_restore(neighbour_list *list, const double *built_at, unsigned long builds)
{
    list->builds = 0; /* forces the build */
    int status = neighbours_update(list, built_at);
    list->builds = builds;
    return status;
}

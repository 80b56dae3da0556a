/* Cell-linked list and a Verlet neighbour list reused by every stage. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Keeps the grid small when the domain is huge compared with the cutoff. */
#define MAX_CELLS_PER_PARTICLE 4
#define MIN_CELL_BUDGET 65536

int neighbours_init(neighbour_list *list, size_t count, double cutoff, double skin,
                    const double domain[4])
{
    memset(list, 0, sizeof *list);
    list->count = count;
    list->cutoff = cutoff;
    list->skin = skin;
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
    list->particle_cell = malloc(count * sizeof *list->particle_cell);
    if (!list->start || !list->built_at || !list->cell_start || !list->cell_cursor ||
        !list->cell_particle || !list->particle_cell) {
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
    free(list->particle_cell);
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

static int needs_rebuild(const neighbour_list *list, const double *position)
{
    if (list->builds == 0 || list->stale)
        return 1;
    double limit2 = 0.25 * list->skin * list->skin;
    for (size_t i = 0; i < list->count; i++) {
        double dx = position[2 * i] - list->built_at[2 * i];
        double dy = position[2 * i + 1] - list->built_at[2 * i + 1];
        if (!(dx * dx + dy * dy <= limit2))
            return 1;
    }
    return 0;
}

/* Counting sort of particles into cells; particles keep index order inside a
 * cell, so the lists come out the same on every run. */
static void sort_into_cells(neighbour_list *list, const double *position)
{
    size_t cells = list->cells[0] * list->cells[1];
    memset(list->cell_start, 0, (cells + 1) * sizeof *list->cell_start);
    for (size_t i = 0; i < list->count; i++) {
        size_t cx = cell_coordinate(position[2 * i], list->origin[0], list->cell_size,
                                    list->cells[0]);
        size_t cy = cell_coordinate(position[2 * i + 1], list->origin[1], list->cell_size,
                                    list->cells[1]);
        list->particle_cell[i] = cy * list->cells[0] + cx;
        list->cell_start[list->particle_cell[i] + 1]++;
    }
    for (size_t c = 0; c < cells; c++)
        list->cell_start[c + 1] += list->cell_start[c];
    memcpy(list->cell_cursor, list->cell_start, cells * sizeof *list->cell_cursor);
    for (size_t i = 0; i < list->count; i++)
        list->cell_particle[list->cell_cursor[list->particle_cell[i]]++] = i;
}

static int compare_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

/* Visits the 3x3 cells around particle i; counts, or also stores, neighbours. */
static size_t gather(const neighbour_list *list, const double *position, size_t i,
                     size_t *out)
{
    double cut2 = list->cutoff * list->cutoff;
    size_t c = list->particle_cell[i];
    long cx = (long)(c % list->cells[0]), cy = (long)(c / list->cells[0]);
    size_t found = 0;
    for (long y = cy - 1; y <= cy + 1; y++) {
        if (y < 0 || y >= (long)list->cells[1])
            continue;
        for (long x = cx - 1; x <= cx + 1; x++) {
            if (x < 0 || x >= (long)list->cells[0])
                continue;
            size_t cell = (size_t)y * list->cells[0] + (size_t)x;
            for (size_t k = list->cell_start[cell]; k < list->cell_start[cell + 1]; k++) {
                size_t j = list->cell_particle[k];
                if (j == i)
                    continue;
                double dx = position[2 * j] - position[2 * i];
                double dy = position[2 * j + 1] - position[2 * i + 1];
                if (dx * dx + dy * dy < cut2) {
                    if (out)
                        out[found] = j;
                    found++;
                }
            }
        }
    }
    if (out)
        qsort(out, found, sizeof *out, compare_size);
    return found;
}

int neighbours_update(neighbour_list *list, const double *position)
{
    if (!needs_rebuild(list, position))
        return MPS2P_OK;
    sort_into_cells(list, position);
    list->start[0] = 0;
    for (size_t i = 0; i < list->count; i++)
        list->start[i + 1] = list->start[i] + gather(list, position, i, NULL);
    size_t total = list->start[list->count];
    if (total > list->capacity) {
        size_t capacity = total + total / 4 + 16;
        size_t *grown = realloc(list->index, capacity * sizeof *grown);
        if (!grown) {
            /* start[] already counts the new pairs, index[] cannot hold them:
             * leave an empty, consistent list and rebuild at the next update
             * even if the particles are back where the last build saw them
             * (a failed step restores them). */
            memset(list->start, 0, (list->count + 1) * sizeof *list->start);
            list->stale = 1;
            return MPS2P_ERR_NOMEM;
        }
        list->index = grown;
        list->capacity = capacity;
    }
    for (size_t i = 0; total > 0 && i < list->count; i++) /* no pairs: index may be NULL */
        gather(list, position, i, list->index + list->start[i]);
    memcpy(list->built_at, position, 2 * list->count * sizeof *position);
    list->builds++;
    list->stale = 0;
    return MPS2P_OK;
}

int neighbours_restore(neighbour_list *list, const double *built_at, unsigned long builds)
{
    list->builds = 0; /* forces the build */
    int status = neighbours_update(list, built_at);
    list->builds = builds;
    return status;
}

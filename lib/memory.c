/* The solver's own memory, counted from what it allocated (arrays of
 * inactive stages are never allocated, so they count nothing). */
#include "internal.h"

size_t solver_memory_bytes(const mps2p_solver *s)
{
    const size_t n = s->count;
    size_t bytes = sizeof *s + (size_t)s->fluid_count * sizeof *s->fluids;
    bytes += n * (sizeof *s->kind + sizeof *s->fluid_id + sizeof *s->density +
                  sizeof *s->viscosity + sizeof *s->on_surface + sizeof *s->rhs +
                  sizeof *s->solution + sizeof *s->unknown_of);
    bytes += 2 * n * sizeof *s->scratch;
    bytes += 2 * 5 * n * sizeof(double); /* state and saved: position, velocity, pressure */
    bytes += n * sizeof *s->number_density;
    if (s->number_density_start)
        bytes += n * sizeof *s->number_density_start;
    if (s->eddy_viscosity)
        bytes += n * sizeof *s->eddy_viscosity;
    if (s->neighbour_count)
        bytes += n * sizeof *s->neighbour_count;
    bytes += phases_memory_bytes(s); /* 0 unless effect two_phase is on */
    const neighbour_list *nl = &s->neighbours;
    bytes += (nl->count + 1) * sizeof *nl->start + nl->capacity * sizeof *nl->index;
    bytes += 2 * nl->count * sizeof *nl->built_at;
    if (nl->short_start) /* the short list */
        bytes += (nl->count + 1) * sizeof *nl->short_start +
                 nl->short_capacity * sizeof *nl->short_index;
    bytes += (2 * nl->cells[0] * nl->cells[1] + 1) * sizeof *nl->cell_start;
    bytes += 2 * nl->count * sizeof *nl->cell_particle;
    bytes += s->matrix.row_capacity * sizeof *s->matrix.row_start;
    bytes += s->matrix.capacity * (sizeof *s->matrix.column + sizeof *s->matrix.value);
    return bytes + linear_solver_memory(s->linear);
}

/* The solver's own memory (statistic memory_bytes), counted from what it
 * allocated (arrays of inactive stages are never allocated, so they count
 * nothing). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "two_phase/two_phase.h"
#include "solver/solver.h"

size_t solver_memory_bytes(const mps2p_solver *s)
{
    const size_t n = s->count;
    size_t bytes = sizeof *s + (size_t)s->fluid_count * sizeof *s->fluids;
    bytes += fields_memory(&solver_fields, s, n); /* on-demand arrays once allocated */
    bytes += sizeof *s->before_step + fields_memory(&solver_fields, s->before_step, n);
    bytes += phases_memory_bytes(s); /* 0 unless effect two_phase is on */
    const neighbour_list *nl = &s->neighbours;
    bytes += (nl->count + 1) * sizeof *nl->start + nl->capacity * sizeof *nl->index;
    bytes += 2 * nl->count * sizeof *nl->built_at;
    if (nl->short_start) /* the short list */
        bytes += (nl->count + 1) * sizeof *nl->short_start +
                 nl->short_capacity * sizeof *nl->short_index;
    bytes += (2 * nl->cells[0] * nl->cells[1] + 1) * sizeof *nl->cell_start;
    bytes += nl->count * sizeof *nl->cell_particle;
    bytes += s->matrix.row_capacity * sizeof *s->matrix.row_start;
    bytes += s->matrix.capacity * (sizeof *s->matrix.column + sizeof *s->matrix.value);
    return bytes + linear_solver_memory(s->linear);
}

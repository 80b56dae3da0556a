/* How much of the light fluid is inside the heavy one (issue 9's measure of
 * entrained air): a light particle counts when it has more heavy-fluid than
 * light-fluid neighbours within re_density (walls not counted), or when it is
 * locally submerged: a heavy-fluid particle above it and a heavy-fluid or
 * wall particle below it, each within 3 l0 vertically and 0.75 l0
 * horizontally ("up" is against gravity). Computed when asked, from the
 * neighbour list. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "two_phase/two_phase.h"

#include <math.h>

int more_liquid_than_light_neighbours(const mps2p_solver *s, size_t i)
{
    const two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows rows = neighbour_rows_within(&s->neighbours, re);
    const double *r = s->state.position;
    int heavy_near = 0, light_near = 0;
    for (size_t k = rows.start[i]; k < rows.start[i + 1]; k++) {
        size_t j = rows.index[k];
        if (s->kind[j] != MPS2P_KIND_FLUID)
            continue;
        double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
        if (dx * dx + dy * dy < re2) {
            heavy_near += !tp->light[j];
            light_near += tp->light[j];
        }
    }
    return heavy_near > light_near;
}

/* Heavy fluid above (against gravity) and heavy fluid or wall below. */
static int submerged(const mps2p_solver *s, size_t i, const double up[2])
{
    const two_phase *tp = s->phases;
    const double l0 = s->l0;
    const neighbour_rows rows = neighbour_rows_within(&s->neighbours, 3.1 * l0);
    const double *r = s->state.position;
    int above = 0, below = 0;
    for (size_t k = rows.start[i]; k < rows.start[i + 1]; k++) {
        size_t j = rows.index[k];
        double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
        double height = dx * up[0] + dy * up[1];
        double across = fabs(dx * up[1] - dy * up[0]);
        if (across >= 0.75 * l0 || fabs(height) >= 3.0 * l0)
            continue;
        int heavy_fluid = s->kind[j] == MPS2P_KIND_FLUID && !tp->light[j];
        above |= heavy_fluid && height > 0.0;
        below |= (heavy_fluid || s->kind[j] == MPS2P_KIND_WALL) && height < 0.0;
    }
    return above && below;
}

size_t gas_in_liquid_count(const mps2p_solver *s)
{
    const two_phase *tp = s->phases;
    if (!tp || !s->neighbours.start)
        return 0;
    double up[2];
    gravity_up(s, up);
    size_t count = 0;
    for (size_t i = 0; i < s->count; i++)
        count += light_in_run(s, i) &&
                 (more_liquid_than_light_neighbours(s, i) || submerged(s, i, up));
    return count;
}

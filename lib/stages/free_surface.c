/* Free surface: particles whose p is 0 at their centre, or half a spacing
 * beyond it (option surface_pressure, stages/pressure.c). Option
 * free_surface:
 *   number_density   n* < beta n0 (Koshizuka and Oka; docs/method.md);
 *   neighbour_count  that, or fewer neighbours within re_density than
 *                    beta_count N0 (N0 those of a lattice particle): the
 *                    count sees a hole beside a particle that a close
 *                    neighbour's large weight hides from n* (after Tanaka and
 *                    Masunaga's auxiliary condition). The count is its own
 *                    stage, in the step only for this variant. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>

/* Lattice points within re (in l0) around one, itself excluded. */
static double lattice_neighbours(double re)
{
    int reach = (int)ceil(re), count = 0;
    for (int y = -reach; y <= reach; y++)
        for (int x = -reach; x <= reach; x++)
            count += (x != 0 || y != 0) && x * x + y * y < re * re;
    return count;
}

int neighbour_count_compute(mps2p_solver *s, double dt)
{
    (void)dt;
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_list *nl = &s->neighbours;
    const double *position = s->state.position;
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
    for (size_t i = 0; i < s->count; i++) {
        unsigned count = 0;
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            count += dx * dx + dy * dy < re2;
        }
        s->neighbour_count[i] = count;
    });
    return MPS2P_OK;
}

int free_surface_detect(mps2p_solver *s, double dt)
{
    (void)dt;
    const double threshold = s->params.beta * s->n0_density;
    const int by_count = s->params.free_surface == FREE_SURFACE_NEIGHBOUR_COUNT;
    const double fewest = s->params.beta_count * lattice_neighbours(s->params.re_density);
    size_t surface = 0; /* a count: the same for any split among threads */
    PARALLEL_FOR(s->params.threads, schedule(static) reduction(+ : surface),
    for (size_t i = 0; i < s->count; i++) {
        int is_surface = kind_carries_pressure(s->kind[i]) &&
                         (s->number_density[i] < threshold ||
                          (by_count && (double)s->neighbour_count[i] < fewest));
        s->on_surface[i] = (unsigned char)is_surface;
        surface += (size_t)is_surface;
    });
    s->surface_particles = surface;
    return MPS2P_OK;
}

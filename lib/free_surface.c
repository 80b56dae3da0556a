/* Free surface: fluid and wall particles with n* < beta n0 get p = 0. */
#include "internal.h"

void free_surface_detect(mps2p_solver *s)
{
    const double threshold = s->params.beta * s->n0_density;
    size_t surface = 0;
    for (size_t i = 0; i < s->count; i++) {
        int is_surface = s->kind[i] != MPS2P_KIND_DUMMY && s->number_density[i] < threshold;
        s->on_surface[i] = (unsigned char)is_surface;
        surface += (size_t)is_surface;
    }
    s->surface_particles = surface;
}

/* How the two phases change the collision model (collision.c asks through
 * s->collision_share): the liquid ignores the gas, the gas bounces off the
 * liquid as off a wall, in the improved model whole in one step inside half
 * a spacing (the damper's rate let a water particle run to 0.3 l0 of an air
 * particle, which then joined the liquid solve at n/n0 = 3.3 and the run
 * diverged: docs/two-phase.md), and a light particle that joined the
 * liquid solve (last step) collides as liquid, half each. Particles of one
 * phase share by mass, and come whole inside collision_core, as without two
 * phases. */
#include "core/core.h"
#include "two_phase/two_phase.h"

double phases_collision_share(const mps2p_solver *s, size_t i, size_t j, int *whole)
{
    const two_phase *tp = s->phases;
    *whole = WHOLE_IN_CORE; /* as without two phases */
    if (tp->light[i] == tp->light[j])
        return s->density[j] / (s->density[i] + s->density[j]);
    if (tp->joined[tp->light[i] ? i : j])
        return 0.5;
    /* the paper's conventional model as it was */
    *whole = tp->light[i] && tp->improved ? WHOLE_IN_HALF : WHOLE_NEVER;
    return tp->light[i] ? 1.0 : -1.0;
}

/* Stage neighbours: the neighbour list brought up to date, at the step's
 * start and after each stage that moves particles (solver/plan.c). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

int neighbours_refresh(mps2p_solver *s, double dt)
{
    (void)dt;
    if (neighbours_update(&s->neighbours, s->state.position) != MPS2P_OK)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "step %llu at t = %.6g s: out of memory for the neighbour list",
                    (unsigned long long)s->steps + 1, s->time);
    return MPS2P_OK;
}

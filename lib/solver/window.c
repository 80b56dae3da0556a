/* Coupling windows: advance to the window's end exactly and say how many
 * steps it took, so that a host can average or check per window. */
#include "core/core.h"
#include "solver/solver.h"

int mps2p_solver_advance_window(mps2p_solver *s, double end_time, uint64_t *steps_taken)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_advance_window: solver is NULL");
    if (steps_taken)
        *steps_taken = 0;
    int status = solver_refuse_if_running(s, "mps2p_solver_advance_window");
    if (status != MPS2P_OK)
        return status;
    const uint64_t before = s->steps;
    status = mps2p_solver_advance_to(s, end_time, NULL, NULL);
    if (steps_taken)
        *steps_taken = s->steps - before; /* steps that succeeded, also on failure */
    return status;
}

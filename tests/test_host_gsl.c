/* The host's GSL error handler is the host's: creating, stepping and
 * destroying solvers (CG and CHOLMOD) leaves the handler the host set in
 * place, and it still runs for the host's own GSL errors. (The library used
 * to switch it off process-wide at the first solver.) */
#include <gsl/gsl_errno.h>
#include "scenes.h"

static int host_calls;
static void host_handler(const char *reason, const char *file, int line, int gsl_errno)
{
    (void)reason, (void)file, (void)line, (void)gsl_errno;
    host_calls++;
}

int main(void)
{
    gsl_set_error_handler(host_handler);
    const char *solvers[] = {"cg", "cholmod"};
    for (int k = 0; k < 2; k++) {
        mps2p_scene *scene = dam_break_scene(0.02);
        MUST(mps2p_scene_set_option(scene, "pressure_solver", solvers[k]));
        mps2p_solver *solver;
        MUST(mps2p_solver_create(scene, &solver));
        for (int step = 0; step < 5; step++)
            MUST(mps2p_solver_step(solver));
        mps2p_solver_destroy(solver);
        mps2p_scene_destroy(scene);
    }
    CHECK(host_calls == 0, "the library's GSL calls reached the handler %d times", host_calls);
    gsl_error_handler_t *now = gsl_set_error_handler(host_handler);
    CHECK(now == host_handler, "the host's GSL error handler was replaced");
    /* a GSL error of the host's own still reaches the host's handler */
    gsl_error("the host's own", __FILE__, __LINE__, GSL_EINVAL);
    CHECK(host_calls == 1, "the host's own GSL error: handler called %d times", host_calls);
    return check_summary("test_host_gsl");
}

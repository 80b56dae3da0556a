/* Divergence detection after a step: non-finite values, particles leaving
 * the domain, pressure spikes and jumps of more than displacement_limit.
 * Fluid particles that leave the domain go out of the run (kind
 * MPS2P_KIND_OUT, as DualSPHysics's excluded particles), up to parameter
 * out_limit's share of the fluid: a spray droplet thrown over a wall does not
 * end a run. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "coupling/coupling.h"

#include <math.h>
#include <stdio.h>

/* What particle i is, for a message: its fluid's name, or a wall and, past
 * body 0 ("walls"), the body it belongs to (a host's moving gate). */
static const char *describe(const mps2p_solver *s, size_t i, char *text, size_t size)
{
    if (kind_is_fluid(s->kind[i]))
        return s->fluids[s->fluid_id[i]].name;
    const char *what = s->kind[i] == MPS2P_KIND_WALL ? "wall" : "dummy wall";
    const int body = s->coupling ? s->coupling->body_of[i] : 0;
    if (body <= 0)
        return what;
    snprintf(text, size, "%s of body \"%s\"", what, s->coupling->bodies[body].name);
    return text;
}

/* Remembers where a divergence was found (statistic diverged_particle). */
int diverged_at(mps2p_solver *s, size_t i, int status)
{
    s->diverged_particle = (long)i;
    return status;
}

static int outside(const mps2p_solver *s, double x, double y)
{
    return x < s->domain[0] || x > s->domain[2] || y < s->domain[1] || y > s->domain[3];
}

static int left_the_domain(mps2p_solver *s, size_t i, double t, const char *why)
{
    const double *r = s->state.position, *u = s->state.velocity;
    char label[96];
    return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                "diverged at step %llu, t = %.6g s: particle %zu (%s) left the domain "
                "[%g, %g] x [%g, %g] at (%g, %g), speed %g m/s%s",
                (unsigned long long)s->steps + 1, t, i, describe(s, i, label, sizeof label),
                s->domain[0], s->domain[2], s->domain[1], s->domain[3], r[2 * i], r[2 * i + 1],
                hypot(u[2 * i], u[2 * i + 1]), why));
}

/* The fluid particles outside the domain leave the run where they are: the
 * step has passed every check, so nothing here is rolled back (kinds are
 * not: solver.c). The neighbour list is built again without them at once,
 * from the positions a checkpoint stores as its reference, so that a solver
 * loaded from one builds the same pairs. */
static void take_out(mps2p_solver *s, size_t leaving)
{
    double *r = s->state.position, *u = s->state.velocity;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID || !outside(s, r[2 * i], r[2 * i + 1]))
            continue;
        s->kind[i] = MPS2P_KIND_OUT;
        u[2 * i] = u[2 * i + 1] = 0.0;
        s->state.pressure[i] = 0.0;
        s->number_density[i] = 0.0; /* no neighbours from now on */
    }
    s->fluid_out += leaving;
    /* out of memory: the list is left stale (empty) and built at the next
     * step's start; the step itself stands */
    (void)neighbours_rebuild(&s->neighbours, r);
}

int divergence_check(mps2p_solver *s, double dt)
{
    const double *r = s->state.position, *u = s->state.velocity, *p = s->state.pressure;
    const double *before = s->before_step->state.position;
    const double jump = s->params.displacement_limit * s->l0;
    /* 0 where the square is not finite: then hypot decides every time */
    const double jump2_within = isfinite(jump * jump) ? jump * jump * (1.0 - 1e-12) : 0.0;
    const double t = s->time + dt;
    const unsigned long long step = (unsigned long long)s->steps + 1;
    char label[96];
    /* fluid at the start: in the run or out of it (kinds only turn FLUID to OUT) */
    size_t fluid = 0, leaving = 0, first_leaving = 0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] == MPS2P_KIND_OUT) { /* out of the run: frozen, checked no more */
            fluid++;
            continue;
        }
        fluid += s->kind[i] == MPS2P_KIND_FLUID;
        const double x = r[2 * i], y = r[2 * i + 1];
        if (!isfinite(x) || !isfinite(y) || !isfinite(u[2 * i]) || !isfinite(u[2 * i + 1]) ||
            !isfinite(p[i]))
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) has a "
                        "non-finite value (position (%g, %g), velocity (%g, %g), p = %g)",
                        step, t, i, describe(s, i, label, sizeof label), x, y, u[2 * i],
                        u[2 * i + 1], p[i]));
        if (outside(s, x, y)) {
            if (s->kind[i] != MPS2P_KIND_FLUID) /* a moving body's particle */
                return left_the_domain(s, i, t, "");
            if (leaving++ == 0)
                first_leaving = i;
        }
        if (fabs(p[i]) > s->pressure_limit)
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) at (%g, %g) "
                        "has pressure %g Pa, beyond the limit %g Pa",
                        step, t, i, describe(s, i, label, sizeof label), x, y, p[i],
                        s->pressure_limit));
        double dx = x - before[2 * i], dy = y - before[2 * i + 1];
        /* hypot (slow) only near or past the limit: below the squared bound
         * the distance is surely within it */
        double moved = jump > 0.0 && !(dx * dx + dy * dy <= jump2_within) ? hypot(dx, dy) : 0.0;
        if (jump > 0.0 && moved > jump)
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) jumped %g l0 "
                        "in one step, to (%g, %g) (limit %g l0)",
                        step, t, i, describe(s, i, label, sizeof label), moved / s->l0, x, y,
                        s->params.displacement_limit));
    }
    if (leaving == 0)
        return MPS2P_OK;
    const double out_limit = s->params.out_limit;
    if ((double)(s->fluid_out + leaving) > out_limit * (double)fluid) {
        char why[256];
        if (out_limit == 0.0)
            snprintf(why, sizeof why, " (out_limit 0: no fluid particle may leave)");
        else
            snprintf(why, sizeof why, "; with %zu leaving this step and %zu out before, more "
                     "than out_limit %g of the %zu fluid particles would be out of the run",
                     leaving, s->fluid_out, out_limit, fluid);
        return left_the_domain(s, first_leaving, t, why);
    }
    take_out(s, leaving);
    return MPS2P_OK;
}

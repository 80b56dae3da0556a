/* The paper's improved model (docs/method.md section 3): the 8-sector scan that
 * sets delta_al per light particle, and the reaction of a triggered light
 * particle on the liquid.
 *
 * Scan (eq. 11-15): circle of radius 1.2 re (re = re_density l0) around light
 * particle i; theta measured counter-clockwise from (1, -1)/sqrt 2; sector a
 * holds (a-1) pi/4 <= theta < a pi/4. Heavy particles in a sector give its
 * representative velocity: max u_x in sectors 1, 2, 5, 6, max u_y in 3, 4, 7,
 * 8. delta_al = 1 when, for some a in 1..4, sectors a and a+4 both hold heavy
 * particles and u_a < u_{a+4}, here u_a + trigger_speed sqrt(|g| l0) <
 * u_{a+4}: the paper's strict inequality fires on the velocity noise of
 * liquid at rest (in still water under air, about half of the air's bottom
 * row every step; docs/two-phase.md), and the threshold, a speed of the
 * particle scale (trigger_speed 1), keeps it to liquid closing faster than
 * it settles: at 0.05 the air under a droplet settling onto the water
 * joined the liquid's solve and held the droplet up for over half a second
 * (docs/two-phase.md, the ladder). Walls and dummies count as heavy particles at
 * rest when sector_scan_walls = 1 (the default: the gas is pinched against
 * walls at impact, which a liquid-only scan misses), but a pair that closes
 * only with a wall in it triggers a light particle inside the liquid only
 * (more liquid than light neighbours; below, in interface_scan). "Enclosed": heavy
 * particles in all 8 sectors. The scan is a stage of effect two_phase (its
 * counts describe the conventional model's squeeze too).
 *
 * Join (stage interface_join, effect interface_reaction: two_step_improved
 * only): a light particle reacts when triggered, or enclosed if
 * join_enclosed = 1, or in an enclosed bubble if join_bubbles = 1 (cut off
 * from the gas's free surface: without it only a bubble's outer ring joins,
 * the liquid solve sees a hole where its core is, holds the ring at the free
 * surface's zero, and the water falls into the bubble; docs/two-phase.md,
 * the ladder's third rung), or, with join_hold, when it reacted in the step
 * before and is still inside the liquid.
 *
 * Reaction (option interface_reaction, one form: drift), the discrete form
 * of delta_al (-grad p)_a in eq. (5), which the paper leaves open: the
 * particle joins the liquid PPE as liquid volume (it counts in the liquid's
 * number density, an unknown with the liquid's density in its source: the
 * liquid cannot close in on it), is moved by the liquid's pressure like the
 * liquid (correction.c), then its velocity relaxes toward the liquid's around
 * it plus a rise velocity (interface_drift_apply). The forms that lost
 * (volume, wall, pair, push, continuity) and their measurements:
 * docs/two-phase.md.
 */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>

#define PI 3.14159265358979323846

static size_t mark_bubbles(mps2p_solver *s);

/* The sector scan over every light particle (eq. 11-15). */
static void scan_sectors(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    const double radius = 1.2 * s->params.re_density * s->l0, r2max = radius * radius;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, radius);
    const double *r = s->state.position, *u = s->state.velocity;
    const int walls = s->params.sector_scan_walls != 0.0;
    const double quarter = PI / 4.0;
    double g[2];
    gravity_acting(s, g);
    const double closing = s->params.trigger_speed * sqrt(hypot(g[0], g[1]) * s->l0);
    size_t triggered = 0, enclosed = 0;
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS reduction(+ : triggered, enclosed),
    for (size_t i = 0; i < s->count; i++) {
        tp->triggered[i] = tp->enclosed[i] = 0;
        if (!light_in_run(s, i))
            continue;
        /* per sector: [0] liquid only, [1] liquid and (with sector_scan_walls) walls */
        int occupied[2][8] = {{0}};
        double rep[2][8];
        for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
            size_t j = nl.index[k];
            double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
            double d2 = dx * dx + dy * dy;
            int liquid = s->kind[j] == MPS2P_KIND_FLUID && !tp->light[j];
            if (!liquid && !(walls && s->kind[j] != MPS2P_KIND_FLUID))
                continue;
            if (d2 > r2max || d2 <= 0.0)
                continue;
            double theta = atan2(dy, dx) + quarter;
            if (theta < 0.0)
                theta += 2.0 * PI;
            int a = (int)(theta / quarter);
            if (a > 7)
                a = 7;
            /* sectors 1, 2, 5, 6 (index 0, 1, 4, 5): horizontal velocity */
            double v = (a == 0 || a == 1 || a == 4 || a == 5) ? u[2 * j] : u[2 * j + 1];
            for (int set = liquid ? 0 : 1; set < 2; set++) {
                if (!occupied[set][a] || v > rep[set][a])
                    rep[set][a] = v;
                occupied[set][a] = 1;
            }
        }
        int all = 1, closes[2] = {0, 0};
        for (int a = 0; a < 8; a++)
            all &= occupied[1][a];
        for (int set = 0; set < 2; set++)
            for (int a = 0; a < 4; a++)
                if (occupied[set][a] && occupied[set][a + 4] &&
                    rep[set][a] + closing < rep[set][a + 4])
                    closes[set] = 1;
        /* A pair closing only with a wall in it triggers gas inside the liquid
         * only: liquid sliding along a wall pinches nothing, and gas ahead of a
         * surge on a dry floor, joined, rode the front (docs/two-phase.md). */
        int trigger = closes[0] || (closes[1] && more_liquid_than_light_neighbours(s, i));
        tp->triggered[i] = (unsigned char)trigger;
        tp->enclosed[i] = (unsigned char)all;
        triggered += (size_t)trigger;
        enclosed += (size_t)all;
    });
    tp->triggered_count = triggered;
    tp->enclosed_count = enclosed;
}

/* The enclosed bubbles ahead of the join (stage interface_join), for it. */
static void mark_bubbles_ahead(mps2p_solver *s)
{
    s->phases->bubbles_ahead = mark_bubbles(s);
    s->phases->bubbles_marked = 1;
}

int interface_scan(mps2p_solver *s, double dt)
{
    (void)dt;
    /* With threads, the join's flood fill (serial: the second thread stood
     * waiting through 0.2 s of the paper's case's first 0.5 s) runs beside the scan:
     * it reads the last step's joins and this step's n*, which the scan
     * does not write, and writes only the bubble marks, which the scan does
     * not read (docs/performance.md). */
    s->phases->bubbles_marked = 0;
    if (team_size(s->params.threads) > 1 && s->effect_active[EFFECT_INTERFACE_REACTION] &&
        s->params.join_bubbles != 0.0)
        SIDE_BY_SIDE(s->params.threads, scan_sectors(s), mark_bubbles_ahead(s));
    else
        scan_sectors(s);
    return MPS2P_OK;
}

/* Enclosed bubbles: light particles with no path through light neighbours
 * within re_density to a light particle on the free surface (n* < beta n0:
 * the top of the air) that was not joined to the liquid's solve in the last
 * step. Breadth first from the free surface. A joined particle does not seed:
 * one particle of a joined bubble whose number density dipped under beta n0
 * released the whole bubble from the liquid's solve at once, the water fell
 * into the hole and the pool bounced up, throwing 200 particles out of the
 * tank (the 8 x 8 bubble, 3 of 8 samplings; docs/two-phase.md). A gas that
 * has no free surface at all (a closed tank full to the lid) is one bubble. */
static size_t mark_bubbles(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    const double threshold = s->params.beta * s->n0_density;
    unsigned char *reached = tp->bubble; /* reached first, then its complement */
    for (size_t i = 0; i < s->count; i++)
        reached[i] = light_in_run(s, i) && s->number_density[i] < threshold && !tp->joined[i];
    light_flood(s, reached, 0);
    size_t count = 0;
    for (size_t i = 0; i < s->count; i++) {
        reached[i] = light_in_run(s, i) && !reached[i];
        count += reached[i];
    }
    return count;
}

int interface_join(mps2p_solver *s, double dt)
{
    (void)dt;
    two_phase *tp = s->phases;
    const int bubbles_on = s->params.join_bubbles != 0.0;
    tp->bubble_count = !bubbles_on ? 0 : tp->bubbles_marked ? tp->bubbles_ahead : mark_bubbles(s);
    tp->bubbles_marked = 0;
    const int hold_on = s->params.join_hold != 0.0;
    const int enclosed_on = s->params.join_enclosed != 0.0;
    size_t joined = 0;
    for (size_t i = 0; i < s->count; i++) {
        tp->was_joined[i] = tp->joined[i];
        tp->joined[i] = 0;
        if (!light_in_run(s, i))
            continue;
        /* Hold: a particle that joined stays joined while it is inside the
         * liquid, so that it does not flicker between the two solves. */
        int hold = tp->was_joined[i] && hold_on && more_liquid_than_light_neighbours(s, i);
        tp->joined[i] =
            (unsigned char)(tp->triggered[i] || hold || (tp->enclosed[i] && enclosed_on) ||
                            (bubbles_on && tp->bubble[i]));
        joined += tp->joined[i];
    }
    tp->joined_count = joined;
    return MPS2P_OK;
}

/* Drift reaction, after the correction: a drift-flux closure. A joined light
 * particle is a bubble carried by the liquid: its velocity relaxes over
 * bubble_relaxation_time tau toward the kernel-weighted mean velocity of the
 * liquid around it plus the terminal rise velocity u_t against gravity
 * (about 0.2-0.25 m/s for 5-20 mm air bubbles in water, Clift, Grace and
 * Weber 1978). The bubble's weight and buoyancy are in u_t, so the gravity
 * this step's explicit stage gave it is taken back first: left in, it takes
 * g tau (0.2 m/s for tau = 0.02 s) off the slip and the bubble does not rise
 * (measured: docs/two-phase.md). Its position follows the correction's
 * convention, r += dt du. Without liquid neighbours nothing is changed. */
int interface_drift_apply(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    double *r = s->state.position, *u = s->state.velocity;
    const double *gravity = s->params.gravity;
    double up[2];
    /* the rise is buoyancy's: none without gravity */
    const double rise = gravity_up(s, up) ? s->params.bubble_rise_velocity : 0.0;
    const int gravity_on = s->effect_active[EFFECT_GRAVITY];
    const double relax = 1.0 - exp(-dt / s->params.bubble_relaxation_time);
    /* a drift bubble reads only liquid neighbours, whom this loop never moves */
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
    for (size_t i = 0; i < s->count; i++) {
        if (!light_in_run(s, i) || !(tp->joined[i] || tp->join_weight[i] > 0.0))
            continue;
        double sw = 0.0, mean[2] = {0.0, 0.0};
        for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
            size_t j = nl.index[k];
            if (s->kind[j] != MPS2P_KIND_FLUID || tp->light[j])
                continue;
            double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
            double d2 = dx * dx + dy * dy;
            if (d2 >= re2 || d2 <= 0.0)
                continue;
            double w = kernel_weight(sqrt(d2), re);
            sw += w;
            mean[0] += w * u[2 * j];
            mean[1] += w * u[2 * j + 1];
        }
        if (!(sw > 0.0))
            continue;
        for (int d = 0; d < 2; d++) {
            double du = gravity_on && s->params.drift_without_gravity != 0.0 ? -dt * gravity[d] : 0.0;
            double target = mean[d] / sw + rise * up[d];
            du += relax * (target - (u[2 * i + d] + du));
            u[2 * i + d] += du;
            r[2 * i + d] += dt * du;
        }
    });
    return MPS2P_OK;
}

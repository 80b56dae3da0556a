/* Which light particles join a seed through light neighbours: the flood fill
 * behind enclosed bubbles (interface_reaction.c) and the open gas
 * (gas_pressure.c). */
#include "two_phase.h"

void light_flood(mps2p_solver *s, unsigned char *reached, int skip_with_liquid)
{
    two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *r = s->state.position;
    long *queue = tp->flood_queue;
    size_t head = 0, tail = 0;
    for (size_t i = 0; i < s->count; i++)
        if (reached[i])
            queue[tail++] = (long)i;
    /* breadth first; the set reached does not depend on the order */
    while (head < tail) {
        size_t i = (size_t)queue[head++];
        for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
            size_t j = nl.index[k];
            if (!tp->light[j] || reached[j] || (skip_with_liquid && moves_with_liquid(s, j)))
                continue;
            double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
            if (dx * dx + dy * dy >= re2)
                continue;
            reached[j] = 1;
            queue[tail++] = (long)j;
        }
    }
}

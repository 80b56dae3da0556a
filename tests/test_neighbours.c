/* The neighbour list's reuse (lib/numerics/neighbours.c): after every update
 * each row holds every particle now closer than cutoff - skin (and the short
 * row every one closer than short_radius), sorted, whether the list was
 * rebuilt or kept; a block moving as one keeps its list where the two
 * largest displacements alone would have rebuilt it; two particles closing
 * in from beyond the cutoff force a build. */
#include "internal.h"
#include "check.h"

#include <string.h>

#define SIDE 12
#define COUNT (SIDE * SIDE)

/* Compares both lists with every pair by brute force; returns the rows that
 * lack a pair or are not sorted. */
static size_t rows_wrong(const neighbour_list *list, const double *r)
{
    const double reach = list->cutoff - list->skin;
    size_t wrong = 0;
    for (size_t i = 0; i < list->count; i++) {
        int bad = 0;
        for (size_t k = list->start[i] + 1; k < list->start[i + 1]; k++)
            bad |= list->index[k - 1] >= list->index[k];
        for (size_t j = 0; j < list->count; j++) {
            double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
            double d = sqrt(dx * dx + dy * dy);
            if (j == i || d >= reach)
                continue;
            int in_long = 0, in_short = 0;
            for (size_t k = list->start[i]; k < list->start[i + 1]; k++)
                in_long |= list->index[k] == j;
            for (size_t k = list->short_start[i]; k < list->short_start[i + 1]; k++)
                in_short |= list->short_index[k] == j;
            bad |= !in_long || (d < list->short_radius && !in_short);
        }
        wrong += bad;
    }
    return wrong;
}

int main(void)
{
    const double l0 = 1.0, cutoff = 3.5, skin = 0.4, short_radius = 2.1;
    const double domain[4] = {-20.0, -20.0, 40.0, 40.0};
    double r[2 * COUNT];
    for (int i = 0; i < COUNT; i++) {
        r[2 * i] = l0 * (i % SIDE);
        r[2 * i + 1] = l0 * (i / SIDE);
    }
    for (double threads = 1; threads <= 2; threads++) {
        neighbour_list list;
        MUST(neighbours_init(&list, COUNT, cutoff, skin, short_radius, domain));
        list.threads = threads;
        double p[2 * COUNT];
        memcpy(p, r, sizeof p);
        MUST(neighbours_update(&list, p));
        CHECK(list.builds == 1 && rows_wrong(&list, p) == 0, "first build");

        /* The block moves as one by 0.3 skin a step: the two largest
         * displacements fill the skin after two steps, no pair closes in. */
        for (int step = 1; step <= 3; step++) {
            for (int i = 0; i < COUNT; i++)
                p[2 * i] = r[2 * i] + 0.3 * skin * step;
            MUST(neighbours_update(&list, p));
            CHECK(rows_wrong(&list, p) == 0, "moving as one, step %d", step);
        }
        CHECK(list.builds == 1, "moving as one: %lu builds, 1 wanted", list.builds);

        /* Past the skin in all: rebuilt (its cells no longer cover it). */
        for (int i = 0; i < COUNT; i++)
            p[2 * i] = r[2 * i] + 1.1 * skin;
        MUST(neighbours_update(&list, p));
        CHECK(list.builds == 2 && rows_wrong(&list, p) == 0, "past the skin: %lu builds",
              list.builds);

        /* The last column, set cutoff + 0.1 skin from the one before it,
         * and that column move toward each other by 0.6 skin each (their
         * pairs end at cutoff - 1.1 skin): the rest is still, so only the
         * rows can tell. One column moving alone closes nothing in. */
        double q[2 * COUNT];
        memcpy(q, p, sizeof q);
        const double gap = cutoff + 0.1 * skin;
        for (int i = 0; i < COUNT; i++)
            if (i % SIDE == SIDE - 1) /* the last column, moved out to gap */
                q[2 * i] = p[2 * i - 2] + gap;
        list.stale = 1;
        MUST(neighbours_update(&list, q));
        unsigned long built = list.builds;
        for (int i = 0; i < COUNT; i++)
            if (i % SIDE == SIDE - 1)
                q[2 * i] -= 0.6 * skin;
        MUST(neighbours_update(&list, q));
        CHECK(rows_wrong(&list, q) == 0 && list.builds == built,
              "one column moved 0.6 skin, nothing closer: %lu builds", list.builds - built);
        for (int i = 0; i < COUNT; i++)
            if (i % SIDE == SIDE - 2)
                q[2 * i] += 0.6 * skin;
        MUST(neighbours_update(&list, q));
        CHECK(list.builds == built + 1, "two columns closed in: %lu builds, 1 wanted",
              list.builds - built);
        CHECK(rows_wrong(&list, q) == 0, "two columns closed in: rows");

        /* Jittered, many steps: every row right after every update. */
        size_t wrong = 0;
        for (int step = 0; step < 60; step++) {
            for (int i = 0; i < 2 * COUNT; i++)
                q[i] += 0.05 * skin * sin(12.9898 * i + 78.233 * step) +
                        (i % 2 == 0 ? 0.12 * skin : 0.0);
            MUST(neighbours_update(&list, q));
            wrong += rows_wrong(&list, q);
        }
        CHECK(wrong == 0, "jittered: %zu rows wrong over 60 updates", wrong);
        neighbours_free(&list);
    }
    return check_summary("test_neighbours");
}

/* Where the threads' blocks of a pair sum split (numerics.h: PAIR_BLOCKS,
 * pair_balance): shares of the rows' entries, moved after each call toward
 * blocks of equal time. Any split gives the same bits, so the shares may
 * follow the clock. */
#include "numerics/numerics.h"

#include <time.h>

/* The least share a block keeps (of an equal one): a block slowed once (the
 * thread descheduled) does not lose its rows for good. */
#define LEAST_SHARE 0.25
/* How far one call moves the shares toward its equal times: the times are
 * noisy, the work changes slowly. */
#define STEP 0.5

double pair_balance_clock(void)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

void pair_balance_prepare(pair_balance *balance, size_t blocks)
{
    if (balance->blocks == blocks)
        return;
    for (size_t b = 0; b <= blocks; b++)
        balance->share[b] = (double)b / (double)blocks;
    balance->blocks = blocks;
}

size_t pair_balance_first(const pair_balance *balance, const size_t *start, size_t count,
                          size_t b)
{
    if (b == 0)
        return 0;
    if (b >= balance->blocks)
        return count;
    const size_t entries = start[count] - start[0];
    return first_row_from(start, count,
                          start[0] + (size_t)(balance->share[b] * (double)entries));
}

void pair_balance_update(pair_balance *balance)
{
    const size_t blocks = balance->blocks;
    double rate[BALANCED_BLOCKS], total = 0.0;
    for (size_t b = 0; b < blocks; b++) {
        const double width = balance->share[b + 1] - balance->share[b];
        const double seconds = balance->seconds[b];
        if (!(seconds > 0.0) || !(width > 0.0))
            return; /* a block too short to time: keep the split */
        rate[b] = width / seconds;
        total += rate[b];
    }
    const double least = LEAST_SHARE / (double)blocks;
    double widths[BALANCED_BLOCKS], sum = 0.0;
    for (size_t b = 0; b < blocks; b++) {
        const double width = balance->share[b + 1] - balance->share[b];
        widths[b] = (1.0 - STEP) * width + STEP * rate[b] / total;
        if (widths[b] < least)
            widths[b] = least;
        sum += widths[b];
    }
    for (size_t b = 0; b < blocks; b++)
        balance->share[b + 1] = balance->share[b] + widths[b] / sum;
    balance->share[blocks] = 1.0;
}

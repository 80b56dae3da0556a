/* Reference constants n0 and lambda of the initial square lattice. */
#include "numerics/numerics.h"

#include <math.h>

void lattice_constants(double l0, double re_in_l0, double *n0, double *lambda)
{
    double re = re_in_l0 * l0;
    int reach = (int)ceil(re_in_l0) + 1;
    double sum_w = 0.0, sum_r2w = 0.0;
    for (int j = -reach; j <= reach; j++) {
        for (int i = -reach; i <= reach; i++) {
            if (i == 0 && j == 0)
                continue;
            double r = l0 * sqrt((double)(i * i + j * j));
            double w = kernel_weight(r, re);
            sum_w += w;
            sum_r2w += r * r * w;
        }
    }
    *n0 = sum_w;
    *lambda = sum_r2w / sum_w;
}

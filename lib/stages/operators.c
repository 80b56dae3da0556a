/* The MPS particle operators (docs/method.md section 1), at one particle. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>

void gradient_at(const mps2p_solver *s, size_t i, const double *field, double reference,
                 double out[2])
{
    gradient_masked_at(s, i, field, reference, NULL, out);
}

/* The gradient of f_j = field[stride * j + offset] with the given reference,
 * over non-dummy neighbours (those of mask, when given) within re_density;
 * with ghosts (a PPE's surface flags), a hydrostatic ghost j contributes
 * rho_i g . r_ij instead of f_j - reference. With sums (not NULL), also the
 * corrective matrix's sums xx, xy, yy over the same pairs, from the same
 * weights (one pass for both: corrected_gradient_at). */
static void gradient_core(const mps2p_solver *s, size_t i, const double *field, size_t stride,
                          size_t offset, double reference, const unsigned char *mask,
                          const unsigned char *ghosts, double out[2], double *sums)
{
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    double g[2];
    gravity_acting(s, g);
    const double hx = s->density[i] * g[0];
    const double hy = s->density[i] * g[1];
    double gx = 0.0, gy = 0.0, xx = 0.0, xy = 0.0, yy = 0.0;
    for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
        size_t j = nl.index[k];
        if (s->kind[j] == MPS2P_KIND_DUMMY || (mask && !mask[j]))
            continue;
        double dx = position[2 * j] - position[2 * i];
        double dy = position[2 * j + 1] - position[2 * i + 1];
        double r2 = dx * dx + dy * dy;
        if (r2 >= re2 || r2 <= 0.0)
            continue;
        double difference = ghosts && is_hydrostatic_ghost(s, ghosts, j)
                                 ? hx * dx + hy * dy
                                 : field[stride * j + offset] - reference;
        double w = kernel_weight(sqrt(r2), re);
        double f = difference / r2 * w;
        gx += f * dx;
        gy += f * dy;
        if (sums) {
            double g = w / r2;
            xx += g * dx * dx;
            xy += g * dx * dy;
            yy += g * dy * dy;
        }
    }
    out[0] = 2.0 / s->n0_density * gx;
    out[1] = 2.0 / s->n0_density * gy;
    if (sums) {
        sums[0] = xx;
        sums[1] = xy;
        sums[2] = yy;
    }
}

void gradient_masked_at(const mps2p_solver *s, size_t i, const double *field, double reference,
                        const unsigned char *mask, double out[2])
{
    gradient_core(s, i, field, 1, 0, reference, mask, NULL, out, NULL);
}

void corrected_gradient_at(const mps2p_solver *s, size_t i, const double *pressure,
                           const unsigned char *mask, const unsigned char *ghosts,
                           double out[2])
{
    double sums[3];
    gradient_core(s, i, pressure, 1, 0, pressure[i], mask, ghosts, out, sums);
    const double scale = 2.0 / s->n0_density;
    double xx = sums[0] * scale, xy = sums[1] * scale, yy = sums[2] * scale;
    /* The identity (det 1) on a full lattice; a particle with neighbours on
     * one side only has a near-singular one: leave it uncorrected rather than
     * amplify noise. */
    double det = xx * yy - xy * xy;
    if (!(det >= CORRECTIVE_MIN_DETERMINANT))
        return;
    double inverse[3] = {yy / det, -xy / det, xx / det};
    double gx = out[0], gy = out[1];
    out[0] = inverse[0] * gx + inverse[1] * gy;
    out[1] = inverse[1] * gx + inverse[2] * gy;
}

void gradient_at_component(const mps2p_solver *s, size_t i, const double *field, int c,
                           double out[2])
{
    gradient_core(s, i, field, 2, (size_t)c, field[2 * i + (size_t)c], NULL, NULL, out, NULL);
}

double minimum_around(const mps2p_solver *s, size_t i, const double *field)
{
    return minimum_masked_around(s, i, field, NULL);
}

double minimum_masked_around(const mps2p_solver *s, size_t i, const double *field,
                             const unsigned char *mask)
{
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    double minimum = field[i];
    for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
        size_t j = nl.index[k];
        if (s->kind[j] == MPS2P_KIND_DUMMY || (mask && !mask[j]))
            continue;
        double dx = position[2 * j] - position[2 * i];
        double dy = position[2 * j + 1] - position[2 * i + 1];
        if (dx * dx + dy * dy < re2 && field[j] < minimum)
            minimum = field[j];
    }
    return minimum;
}

void laplacian_at(const mps2p_solver *s, size_t i, const double *field, size_t components,
                  double *out)
{
    laplacian_masked_at(s, i, field, components, NULL, out);
}

void laplacian_masked_at(const mps2p_solver *s, size_t i, const double *field,
                         size_t components, const unsigned char *mask, double *out)
{
    const double re = s->params.re_laplacian * s->l0;
    const neighbour_list *nl = &s->neighbours;
    const double *position = s->state.position;
    const double factor = 2.0 * 2 / (s->lambda * s->n0_laplacian);
    for (size_t c = 0; c < components; c++)
        out[c] = 0.0;
    for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
        size_t j = nl->index[k];
        if (mask && !mask[j])
            continue;
        double dx = position[2 * j] - position[2 * i];
        double dy = position[2 * j + 1] - position[2 * i + 1];
        double w = kernel_weight_squared(dx * dx + dy * dy, re);
        if (w == 0.0)
            continue;
        for (size_t c = 0; c < components; c++)
            out[c] += (field[components * j + c] - field[components * i + c]) * w;
    }
    for (size_t c = 0; c < components; c++)
        out[c] *= factor;
}

/* MPS operators on a regular lattice: n0, the gradient of a linear field and
 * the Laplacian of a quadratic field, at an interior particle. */
#include "internal.h"
#include "check.h"

#include <string.h>

static mps2p_solver *lattice(double l0, int side, double jitter)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(l0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 0.0, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, side * l0, side * l0));
    if (jitter > 0.0) {
        /* perturb the lattice by a fixed pseudo-random pattern */
        size_t n;
        MUST(mps2p_scene_particle_count(scene, &n));
        for (size_t i = 0; i < 2 * n; i++)
            scene->position[i] += jitter * l0 * sin(12.9898 * (double)i + 78.233);
    }
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    return solver;
}

/* The short neighbour list: row by row, the long list's pairs closer than
 * re_density l0 + skin, in the same order, and nothing else. */
static void check_short_list(const mps2p_solver *s)
{
    const neighbour_list *nl = &s->neighbours;
    CHECK(nl->short_start != NULL, "a solver keeps a short neighbour list");
    if (!nl->short_start)
        return;
    const double cut = nl->short_radius + nl->skin;
    const double *r = nl->built_at;
    size_t mismatches = 0;
    for (size_t i = 0; i < nl->count; i++) {
        size_t next = nl->short_start[i];
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
            if (dx * dx + dy * dy < cut * cut)
                mismatches += next >= nl->short_start[i + 1] || nl->short_index[next++] != j;
        }
        mismatches += next != nl->short_start[i + 1];
    }
    CHECK(mismatches == 0, "short list: %zu rows or pairs differ from the long list's", mismatches);
    /* pairs go as the area within the cut: the short list's share is about
     * ((re_density + skin) / cutoff)^2 (0.51 at re_laplacian 3.1), more near
     * the lattice's edges */
    const double share = (double)nl->short_start[nl->count] / (double)nl->start[nl->count];
    const double expected = cut * cut / (nl->cutoff * nl->cutoff);
    CHECK(share < expected + 0.1, "short list holds %zu pairs, the long %zu (share %.3f, about "
          "%.3f expected)", nl->short_start[nl->count], nl->start[nl->count], share, expected);
    neighbour_rows rows = neighbour_rows_within(nl, s->params.re_density * s->l0);
    CHECK(rows.start == nl->short_start, "the density radius loops over the short list");
    rows = neighbour_rows_within(nl, 1.2 * s->params.re_density * s->l0);
    CHECK(rows.start == nl->start, "beyond the density radius, the long list");
}

int main(void)
{
    const double l0 = 0.01;
    const int side = 21;
    mps2p_solver *s = lattice(l0, side, 0.0);
    const size_t centre = (size_t)(side / 2) * side + side / 2;

    /* n0 by hand for re = 2.1 l0: 4 neighbours at l0, 4 at sqrt(2) l0, 4 at 2 l0 */
    double by_hand = 4 * (2.1 - 1) + 4 * (2.1 / sqrt(2.0) - 1) + 4 * (2.1 / 2 - 1);
    CHECK_CLOSE(s->n0_density, by_hand, 1e-12, "n0 for re = 2.1 l0");
    CHECK_CLOSE(s->number_density[centre], s->n0_density, 1e-12 * by_hand,
                "number density of the interior particle");
    double at_corner = s->number_density[0];
    CHECK(at_corner < 0.5 * s->n0_density, "corner particle must be far below n0, got %g",
          at_corner);

    /* fields on the particles */
    size_t n = s->count;
    double *linear = malloc(n * sizeof *linear), *quadratic = malloc(n * sizeof *quadratic);
    double *vector = malloc(2 * n * sizeof *vector);
    for (size_t i = 0; i < n; i++) {
        double x = s->state.position[2 * i], y = s->state.position[2 * i + 1];
        linear[i] = 3.0 + 2.0 * x - 5.0 * y;
        quadratic[i] = x * x + y * y;
        vector[2 * i] = x * x;          /* lap = 2 */
        vector[2 * i + 1] = 3.0 * y * y; /* lap = 6 */
    }
    double g[2];
    gradient_at(s, centre, linear, linear[centre], g);
    CHECK_CLOSE(g[0], 2.0, 1e-9, "d/dx of 3 + 2x - 5y");
    CHECK_CLOSE(g[1], -5.0, 1e-9, "d/dy of 3 + 2x - 5y");
    double lap;
    laplacian_at(s, centre, quadratic, 1, &lap);
    CHECK_CLOSE(lap, 4.0, 1e-9, "Laplacian of x^2 + y^2");
    double lap2[2];
    laplacian_at(s, centre, vector, 2, lap2);
    CHECK_CLOSE(lap2[0], 2.0, 1e-9, "Laplacian of x^2 (vector component)");
    CHECK_CLOSE(lap2[1], 6.0, 1e-9, "Laplacian of 3y^2 (vector component)");
    CHECK_CLOSE(minimum_around(s, centre, linear),
                linear[centre] - 5.0 * 2 * l0 - 2.0 * 0 * l0, 1e-12,
                "minimum of the linear field within 2.1 l0 (two rows up)");
    mps2p_solver_destroy(s);

    /* On a lattice perturbed by 5 % of l0 the operators are approximate:
     * the errors are reported, and bounded loosely. */
    s = lattice(l0, side, 0.05);
    check_short_list(s);
    for (size_t i = 0; i < n; i++) {
        double x = s->state.position[2 * i], y = s->state.position[2 * i + 1];
        linear[i] = 3.0 + 2.0 * x - 5.0 * y;
        quadratic[i] = x * x + y * y;
    }
    gradient_at(s, centre, linear, linear[centre], g);
    laplacian_at(s, centre, quadratic, 1, &lap);
    printf("perturbed lattice (5%% of l0): gradient (%.4f, %.4f) vs (2, -5); "
           "Laplacian %.4f vs 4\n", g[0], g[1], lap);
    CHECK(fabs(g[0] - 2.0) < 0.3 && fabs(g[1] + 5.0) < 0.75,
          "gradient on the perturbed lattice off by more than 15 %%");
    CHECK(fabs(lap - 4.0) < 0.6, "Laplacian on the perturbed lattice off by more than 15 %%");
    mps2p_solver_destroy(s);
    free(linear);
    free(quadratic);
    free(vector);
    return check_summary("test_operators");
}

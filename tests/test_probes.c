/* Point probes agree with a weighted average computed by hand from the
 * particles; air is outside; the front of a fresh dam break is the column's
 * width; bad arguments are refused. */
#include <string.h>
#include "scenes.h"

typedef struct particles {
    size_t n;
    double *position, *velocity, *pressure;
    int *kind;
} particles;

static particles fetch(const mps2p_solver *solver)
{
    particles p;
    MUST(mps2p_solver_particle_count(solver, &p.n));
    p.position = malloc(2 * p.n * sizeof(double));
    p.velocity = malloc(2 * p.n * sizeof(double));
    p.pressure = malloc(p.n * sizeof(double));
    p.kind = malloc(p.n * sizeof(int));
    MUST(mps2p_solver_get_positions(solver, p.position, 2 * p.n));
    MUST(mps2p_solver_get_velocities(solver, p.velocity, 2 * p.n));
    MUST(mps2p_solver_get_pressure(solver, p.pressure, p.n));
    MUST(mps2p_solver_get_kinds(solver, p.kind, p.n));
    return p;
}

/* The documented rule, over all particles: the reference for the probe. */
static void by_hand(const particles *p, double re, double threshold, const double point[2],
                    double *pressure, double velocity[2], int *inside)
{
    double all = 0, wp = 0, fluid = 0, wu[2] = {0, 0};
    for (size_t j = 0; j < p->n; j++) {
        if (p->kind[j] == MPS2P_KIND_DUMMY)
            continue;
        double r = hypot(p->position[2 * j] - point[0], p->position[2 * j + 1] - point[1]);
        if (r >= re)
            continue;
        double w = re / r - 1.0;
        all += w;
        wp += w * p->pressure[j];
        if (p->kind[j] == MPS2P_KIND_FLUID) {
            fluid += w;
            wu[0] += w * p->velocity[2 * j];
            wu[1] += w * p->velocity[2 * j + 1];
        }
    }
    *inside = fluid >= threshold;
    *pressure = *inside ? wp / all : 0.0;
    velocity[0] = *inside ? wu[0] / fluid : 0.0;
    velocity[1] = *inside ? wu[1] / fluid : 0.0;
}

static void release(particles *p)
{
    free(p->position);
    free(p->velocity);
    free(p->pressure);
    free(p->kind);
}

int main(void)
{
    /* 1. a still tank, 0.4 m wide and 0.2 m deep, after a few steps */
    const double l0 = 0.02, depth = 0.2;
    mps2p_scene *scene = tank_scene(l0, 0.4, depth);
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    for (int k = 0; k < 10; k++)
        MUST(mps2p_solver_step(solver));
    particles p = fetch(solver);
    double n0;
    MUST(mps2p_solver_get_stat(solver, "n0", &n0));
    const double re = 2.1 * l0, threshold = 0.5 * 0.97 * n0;

    /* a grid of points through water, surface, walls and air */
    enum { NX = 23, NY = 20, COUNT = NX * NY };
    double points[2 * COUNT], pressure[COUNT], velocity[2 * COUNT];
    int inside[COUNT];
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++) {
            points[2 * (j * NX + i)] = -0.05 + 0.5 * i / (NX - 1);
            points[2 * (j * NX + i) + 1] = -0.05 + 0.4 * j / (NY - 1);
        }
    MUST(mps2p_solver_probe(solver, COUNT, points, pressure, velocity, inside));
    int disagreements = 0, inside_count = 0;
    for (int k = 0; k < COUNT; k++) {
        double hand_p, hand_u[2];
        int hand_in;
        by_hand(&p, re, threshold, &points[2 * k], &hand_p, hand_u, &hand_in);
        inside_count += inside[k];
        double scale = fmax(1.0, fabs(hand_p));
        if (inside[k] != hand_in || fabs(pressure[k] - hand_p) > 1e-9 * scale ||
            fabs(velocity[2 * k] - hand_u[0]) > 1e-12 ||
            fabs(velocity[2 * k + 1] - hand_u[1]) > 1e-12) {
            if (disagreements++ < 5)
                fprintf(stderr, "point (%g, %g): probe %d %g (%g, %g), by hand %d %g (%g, %g)\n",
                        points[2 * k], points[2 * k + 1], inside[k], pressure[k],
                        velocity[2 * k], velocity[2 * k + 1], hand_in, hand_p, hand_u[0],
                        hand_u[1]);
        }
    }
    CHECK(disagreements == 0, "%d of %d points disagree with the hand computation",
          disagreements, COUNT);
    CHECK(inside_count > COUNT / 5, "only %d of %d points inside", inside_count, COUNT);

    /* mid-depth, and in the air above the water */
    double probe_points[6] = {0.2, 0.1, 0.2, depth + 0.08, p.position[0], p.position[1]};
    double probe_p[3], probe_u[6];
    int probe_in[3];
    MUST(mps2p_solver_probe(solver, 3, probe_points, probe_p, probe_u, probe_in));
    double hand_p, hand_u[2];
    int hand_in;
    by_hand(&p, re, threshold, probe_points, &hand_p, hand_u, &hand_in);
    printf("probe at mid-depth: %.6g Pa (by hand %.6g Pa, hydrostatic %.6g Pa)\n", probe_p[0],
           hand_p, 1000.0 * 9.81 * (depth - 0.1));
    CHECK(probe_in[0] == 1, "mid-depth point is not inside");
    CHECK_CLOSE(probe_p[0], hand_p, 1e-9 * fabs(hand_p), "mid-depth pressure against the hand sum");
    CHECK(probe_p[0] > 0.0, "no pressure at mid-depth");
    CHECK(probe_in[1] == 0 && probe_p[1] == 0.0 && probe_u[2] == 0.0 && probe_u[3] == 0.0,
          "a point in the air is inside (%d) or carries values (%g Pa)", probe_in[1],
          probe_p[1]);
    CHECK(isfinite(probe_p[2]), "a point on a particle gives %g", probe_p[2]);
    /* optional outputs */
    MUST(mps2p_solver_probe(solver, 1, probe_points, probe_p, NULL, NULL));
    CHECK(probe_p[0] == hand_p || fabs(probe_p[0] - hand_p) <= 1e-9 * fabs(hand_p),
          "without optional outputs: %g", probe_p[0]);
    release(&p);

    /* argument errors */
    double nan_point[2] = {NAN, 0.0};
    CHECK(mps2p_solver_probe(NULL, 1, probe_points, probe_p, NULL, NULL) == MPS2P_ERR_NULL,
          "NULL solver");
    CHECK(mps2p_solver_probe(solver, 1, NULL, probe_p, NULL, NULL) == MPS2P_ERR_NULL,
          "NULL points");
    CHECK(mps2p_solver_probe(solver, 1, probe_points, NULL, NULL, NULL) == MPS2P_ERR_NULL,
          "NULL pressure");
    CHECK(mps2p_solver_probe(solver, 1, nan_point, probe_p, NULL, NULL) == MPS2P_ERR_INVALID &&
              strstr(mps2p_last_error(), "not finite"),
          "NaN point: %s", mps2p_last_error());
    CHECK(mps2p_solver_probe(solver, 0, NULL, NULL, NULL, NULL) == MPS2P_OK, "no points");
    mps2p_solver_destroy(solver);

    /* 2. the front of a fresh dam break is the column's width, 0.15 m */
    scene = dam_break_scene(0.01);
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    double front;
    MUST(mps2p_solver_front(solver, -1, INFINITY, &front));
    CHECK_CLOSE(front, 0.15, 1e-12, "front of any fluid");
    MUST(mps2p_solver_front(solver, 0, 0.05, &front));
    CHECK_CLOSE(front, 0.15, 1e-12, "front of water below 0.05 m");
    CHECK(mps2p_solver_front(solver, 0, -1.0, &front) == MPS2P_ERR_INVALID &&
              strstr(mps2p_last_error(), "water"),
          "nothing below y = -1: %s", mps2p_last_error());
    CHECK(mps2p_solver_front(solver, 3, 1.0, &front) == MPS2P_ERR_INVALID, "fluid 3");
    CHECK(mps2p_solver_front(solver, -2, 1.0, &front) == MPS2P_ERR_INVALID, "fluid -2");
    CHECK(mps2p_solver_front(solver, -1, NAN, &front) == MPS2P_ERR_INVALID, "NaN height");
    CHECK(mps2p_solver_front(solver, -1, 1.0, NULL) == MPS2P_ERR_NULL, "NULL output");
    CHECK(mps2p_solver_front(NULL, -1, 1.0, &front) == MPS2P_ERR_NULL, "NULL solver");
    mps2p_solver_destroy(solver);
    return check_summary("test_probes");
}

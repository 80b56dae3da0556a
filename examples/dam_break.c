/* Water-only dam break (Martin & Moyce's n^2 = 2 column, the paper's case
 * without air): builds the scene, runs it, prints the surge front.
 *
 *   dam_break [l0 [end_time [snapshot_dir]]]
 *
 * Prints t, T = t sqrt(2g/a), Z = z/a every 0.01 s of simulated time, where z
 * is the front on the floor measured from the left wall and a = 0.15 m. With
 * snapshot_dir, also writes snapshot_<ms>.csv (x, y, u, v, p, kind) every 0.1 s. */
#include <mps2p.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define WIDTH 0.15   /* column width a (m) */
#define HEIGHT 0.30  /* column height 2a (m) */
#define TANK 0.60    /* tank width (m) */

static int check(int status, const char *what);

static void write_snapshot(const mps2p_solver *solver, const char *dir, double t)
{
    size_t n;
    check(mps2p_solver_particle_count(solver, &n), "count");
    double *r = malloc(2 * n * sizeof *r), *u = malloc(2 * n * sizeof *u);
    double *p = malloc(n * sizeof *p);
    int *kind = malloc(n * sizeof *kind);
    if (!r || !u || !p || !kind)
        exit(1);
    check(mps2p_solver_get_positions(solver, r, 2 * n), "positions");
    check(mps2p_solver_get_velocities(solver, u, 2 * n), "velocities");
    check(mps2p_solver_get_pressure(solver, p, n), "pressure");
    check(mps2p_solver_get_kinds(solver, kind, n), "kinds");
    char path[1024];
    snprintf(path, sizeof path, "%s/snapshot_%04d.csv", dir, (int)lround(t * 1000));
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    fprintf(f, "x,y,u,v,p,kind\n");
    for (size_t i = 0; i < n; i++)
        fprintf(f, "%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", r[2 * i], r[2 * i + 1], u[2 * i],
                u[2 * i + 1], p[i], kind[i]);
    fclose(f);
    free(r);
    free(u);
    free(p);
    free(kind);
}

static int check(int status, const char *what)
{
    if (status < 0) {
        fprintf(stderr, "%s: %s: %s\n", what, mps2p_status_string(status), mps2p_last_error());
        exit(1);
    }
    return status;
}

/* Rightmost fluid particle in the two lowest layers, plus half a spacing. */
static double front(const mps2p_solver *solver, double l0)
{
    size_t n;
    check(mps2p_solver_particle_count(solver, &n), "count");
    double *r = malloc(2 * n * sizeof *r);
    int *kind = malloc(n * sizeof *kind);
    if (!r || !kind)
        exit(1);
    check(mps2p_solver_get_positions(solver, r, 2 * n), "positions");
    check(mps2p_solver_get_kinds(solver, kind, n), "kinds");
    double z = 0.0;
    for (size_t i = 0; i < n; i++)
        if (kind[i] == MPS2P_KIND_FLUID && r[2 * i + 1] < 2.0 * l0 && r[2 * i] > z)
            z = r[2 * i];
    free(r);
    free(kind);
    return z + 0.5 * l0;
}

int main(int argc, char **argv)
{
    double l0 = argc > 1 ? atof(argv[1]) : 0.01;
    double end = argc > 2 ? atof(argv[2]) : 0.3;
    const char *snapshot_dir = argc > 3 ? argv[3] : NULL;

    mps2p_scene *scene;
    int water;
    check(mps2p_scene_create(l0, &scene), "scene");
    check(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water), "fluid");
    check(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, WIDTH, HEIGHT), "water column");
    check(mps2p_scene_add_tank(scene, 0.0, 0.0, TANK, 0.7, 1), "tank");

    mps2p_solver *solver;
    check(mps2p_solver_create(scene, &solver), "solver");
    mps2p_scene_destroy(scene);

    const double g = 9.81, scale = sqrt(2.0 * g / WIDTH);
    printf("# t(s) T Z steps\n");
    for (int k = 1; k * 0.01 <= end + 1e-9; k++) {
        int status = mps2p_solver_advance_to(solver, k * 0.01, NULL, NULL);
        if (status < 0) {
            fprintf(stderr, "%s\n", mps2p_solver_last_error(solver));
            break;
        }
        uint64_t steps;
        double t;
        mps2p_solver_get_step_count(solver, &steps);
        mps2p_solver_get_time(solver, &t);
        printf("%.3f %.4f %.4f %llu\n", t, t * scale, front(solver, l0) / WIDTH,
               (unsigned long long)steps);
        if (snapshot_dir && k % 10 == 0)
            write_snapshot(solver, snapshot_dir, t);
    }
    mps2p_solver_destroy(solver);
    return 0;
}

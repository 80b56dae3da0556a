/* Paper's case harness: water column 0.15 x 0.3 at the left of a 0.6 m tank,
 * air filling the rest up to 0.7 m, open top, l0 = 0.01.
 * usage: harness END [key=value ...] [opt:key=value ...] [noair] [snap=DIR] [snapat=t1,t2,...]
 * "air in water" (printed as inw): air particle with (a) more water than air
 * neighbours within re_density (2.1 l0; walls not counted), or (b) locally
 * submerged: a water particle above it (0 < dy < 3 l0, |dx| < 0.75 l0) and a
 * water or wall particle below it (0 < -dy < 3 l0, |dx| < 0.75 l0). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <mps2p.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define L0 0.01
static int water = 0, air = 1;
static double cmax = 0, gmax_p = 0, tmax = 0, emax = 0, jmax = 0, iters = 0, giters = 0; static long nsteps = 0;

static int progress(const mps2p_solver *s, void *u)
{
    (void)u;
    double v;
    if (mps2p_solver_get_stat(s, "gas_pressure_max", &v) == 0 && v > gmax_p) gmax_p = v;
    if (mps2p_solver_get_stat(s, "gas_triggered", &v) == 0 && v > tmax) tmax = v;
    if (mps2p_solver_get_stat(s, "gas_enclosed", &v) == 0 && v > emax) emax = v;
    if (mps2p_solver_get_stat(s, "gas_joined", &v) == 0 && v > jmax) jmax = v;
    if (mps2p_solver_get_stat(s, "gas_capped", &v) == 0 && v > cmax) cmax = v;
    mps2p_solver_get_stat(s, "ppe_iterations", &v); iters += v;
    if (mps2p_solver_get_stat(s, "gas_ppe_iterations", &v) == 0) giters += v;
    nsteps++;
    return 0;
}

static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }

int main(int argc, char **argv)
{
    double end = atof(argv[1]);
    int noair = 0; const char *snapdir = NULL; double snapat[64]; int nsnap = 0;
    mps2p_scene *sc;
    mps2p_scene_create(L0, &sc);
    mps2p_scene_add_fluid(sc, "water", 1000.0, 1e-6, &water);
    for (int a = 2; a < argc; a++) if (!strcmp(argv[a], "noair")) noair = 1;
    if (!noair) mps2p_scene_add_fluid(sc, "air", 1.2, 1.5e-5, &air);
    mps2p_scene_set_option(sc, "pressure_solver", "cg");
    mps2p_scene_set_param(sc, "dt", 2e-4);
    for (int a = 2; a < argc; a++) {
        char key[128], val[128];
        if (!strncmp(argv[a], "snap=", 5)) { snapdir = argv[a] + 5; continue; }
        if (!strncmp(argv[a], "snapat=", 7)) { char *p = argv[a] + 7; while (*p) { snapat[nsnap++] = strtod(p, &p); if (*p == ',') p++; } continue; }
        if (!strcmp(argv[a], "noair")) continue;
        if (!strncmp(argv[a], "opt:", 4)) {
            sscanf(argv[a] + 4, "%127[^=]=%127s", key, val);
            if (mps2p_scene_set_option(sc, key, val)) { fprintf(stderr, "%s\n", mps2p_last_error()); return 2; }
        } else {
            sscanf(argv[a], "%127[^=]=%127s", key, val);
            if (mps2p_scene_set_param(sc, key, atof(val))) { fprintf(stderr, "%s\n", mps2p_last_error()); return 2; }
        }
    }
    mps2p_scene_add_fluid_box(sc, water, 0.0, 0.0, 0.15, 0.30);
    if (!noair) {
        mps2p_scene_add_fluid_box(sc, air, 0.15, 0.0, 0.6, 0.7);
        mps2p_scene_add_fluid_box(sc, air, 0.0, 0.3, 0.15, 0.7);
    }
    mps2p_scene_add_tank(sc, 0.0, 0.0, 0.6, getenv("TANK_H") ? atof(getenv("TANK_H")) : 1.2, 1);
    mps2p_scene_set_domain(sc, -10.0, -0.5, 10.6, 20.0);
    mps2p_solver *s;
    if (mps2p_solver_create(sc, &s)) { fprintf(stderr, "create: %s\n", mps2p_last_error()); return 2; }
    size_t n; mps2p_solver_particle_count(s, &n);
    double *r = malloc(2 * n * sizeof *r), *u = malloc(2 * n * sizeof *u), *p = malloc(n * sizeof *p);
    int *fid = malloc(n * sizeof *fid), *kind = malloc(n * sizeof *kind);
    mps2p_solver_get_kinds(s, kind, n);
    mps2p_solver_get_fluid_ids(s, fid, n);
    size_t nw = 0, na = 0;
    for (size_t i = 0; i < n; i++) { if (kind[i] == 0 && fid[i] == water) nw++; if (kind[i] == 0 && fid[i] == air && !noair) na++; }
    printf("# particles %zu water %zu air %zu\n", n, nw, na);
    printf("#    t  steps  inw inwA  trig  encl  join   gasPmax  uwat   uair  front  wPmax  itW  itG  wall_s cap\n");
    double t0 = now(), peak = 0, last_inw = 0; int status = 0; int si = 0;
    const double re = 2.1 * L0;
    for (int k = 1; k <= (int)lround(end / 0.05); k++) {
        cmax = gmax_p = tmax = emax = jmax = iters = giters = 0; nsteps = 0;
        double target = 0.05 * k;
        status = mps2p_solver_advance_to(s, target, progress, NULL);
        double t; mps2p_solver_get_time(s, &t);
        mps2p_solver_get_positions(s, r, 2 * n);
        mps2p_solver_get_velocities(s, u, 2 * n);
        mps2p_solver_get_pressure(s, p, n);
        size_t inw = 0, inwa = 0; double uw = 0, ua = 0, front = 0, wp = 0;
        for (size_t i = 0; i < n; i++) {
            if (kind[i] != 0) continue;
            double sp = hypot(u[2 * i], u[2 * i + 1]);
            if (fid[i] == water) { uw = fmax(uw, sp); wp = fmax(wp, p[i]); if (r[2 * i + 1] < 2 * L0) front = fmax(front, r[2 * i] + 0.5 * L0); continue; }
            int cw = 0, ca = 0, above = 0, below = 0;
            for (size_t j = 0; j < n; j++) {
                if (j == i) continue;
                double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
                if (fabs(dx) > 3 * L0 || fabs(dy) > 3 * L0) continue;
                int isw = kind[j] == 0 && fid[j] == water;
                if (dx * dx + dy * dy < re * re && kind[j] == 0) { if (isw) cw++; else ca++; }
                if (fabs(dx) < 0.75 * L0) {
                    if (isw && dy > 0) above = 1;
                    /* a wall or dummy, not fluid out of the run (kind 3) */
                    if ((isw || kind[j] == 1 || kind[j] == 2) && dy < 0) below = 1;
                }
            }
            int a_ = cw > ca; int b_ = above && below;
            inwa += a_; inw += (a_ || b_);
            ua = fmax(ua, sp);
        }
        if (inw > peak) peak = inw;
        last_inw = inw;
        printf("%6.2f %6ld %4zu %4zu %5.0f %5.0f %5.0f %9.1f %5.2f %6.2f %6.3f %6.0f %4.0f %4.0f %7.1f %3.0f\n", t, nsteps, inw, inwa, tmax, emax, jmax,
               gmax_p, uw, ua, front, wp, nsteps ? iters / nsteps : 0, nsteps ? giters / nsteps : 0, now() - t0, cmax);
        fflush(stdout);
        if (snapdir && si < nsnap && t >= snapat[si] - 1e-9) {
            char path[512]; snprintf(path, sizeof path, "%s/snap_%05.3f.csv", snapdir, t);
            FILE *f = fopen(path, "w"); fprintf(f, "x,y,kind,fluid,p,u,v\n");
            for (size_t i = 0; i < n; i++) fprintf(f, "%g,%g,%d,%d,%g,%g,%g\n", r[2*i], r[2*i+1], kind[i], fid[i], p[i], u[2*i], u[2*i+1]);
            fclose(f); si++;
        }
        if (status != 0) break;
    }
    double t; mps2p_solver_get_time(s, &t);
    printf("# END status %s t %.4f peak_inw %.0f final_inw %.0f wall %.1f s (%.1f s per sim s)\n", mps2p_status_string(status), t, peak, last_inw, now() - t0, (now() - t0) / fmax(t, 1e-9));
    if (status) printf("# %s\n", mps2p_solver_last_error(s));
    return 0;
}

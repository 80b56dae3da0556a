/* Spray leaving the domain (parameter out_limit, kind MPS2P_KIND_OUT): the
 * droplets that cross the domain's edge go out of the run and the rest keeps
 * stepping; out of the run they are frozen, at rest, without pressure and
 * nobody's neighbour, and statistic fluid_out counts them; a checkpoint
 * written after they left restarts bit for bit, a saved state from before
 * puts them back in the run and gives the same run again, and a checkpoint
 * whose count does not fit its kinds is refused. */
#define _POSIX_C_SOURCE 200809L
#include <hdf5.h>
#include <string.h>
#include <unistd.h>
#include "checkpoint_seal.h"
#include "scenes.h"

#define AFTER 30 /* steps after the last droplet left */

typedef struct snapshot {
    size_t n;
    double *position, *velocity, *pressure, *density;
    int *kind, *fluid_id;
    double time, fluid_out;
    uint64_t steps;
} snapshot;

static snapshot take(const mps2p_solver *solver)
{
    snapshot s;
    MUST(mps2p_solver_particle_count(solver, &s.n));
    s.position = malloc(2 * s.n * sizeof(double));
    s.velocity = malloc(2 * s.n * sizeof(double));
    s.pressure = malloc(s.n * sizeof(double));
    s.density = malloc(s.n * sizeof(double));
    s.kind = malloc(s.n * sizeof(int));
    s.fluid_id = malloc(s.n * sizeof(int));
    MUST(mps2p_solver_get_positions(solver, s.position, 2 * s.n));
    MUST(mps2p_solver_get_velocities(solver, s.velocity, 2 * s.n));
    MUST(mps2p_solver_get_pressure(solver, s.pressure, s.n));
    MUST(mps2p_solver_get_number_density(solver, s.density, s.n));
    MUST(mps2p_solver_get_kinds(solver, s.kind, s.n));
    MUST(mps2p_solver_get_fluid_ids(solver, s.fluid_id, s.n));
    MUST(mps2p_solver_get_time(solver, &s.time));
    MUST(mps2p_solver_get_step_count(solver, &s.steps));
    MUST(mps2p_solver_get_stat(solver, "fluid_out", &s.fluid_out));
    return s;
}

static void release(snapshot *s)
{
    free(s->position);
    free(s->velocity);
    free(s->pressure);
    free(s->density);
    free(s->kind);
    free(s->fluid_id);
}

static int same(const snapshot *a, const snapshot *b)
{
    return a->n == b->n && a->steps == b->steps && !memcmp(&a->time, &b->time, sizeof a->time) &&
           a->fluid_out == b->fluid_out &&
           !memcmp(a->position, b->position, 2 * a->n * sizeof(double)) &&
           !memcmp(a->velocity, b->velocity, 2 * a->n * sizeof(double)) &&
           !memcmp(a->pressure, b->pressure, a->n * sizeof(double)) &&
           !memcmp(a->kind, b->kind, a->n * sizeof(int));
}

static size_t count_kind(const snapshot *s, int kind)
{
    size_t count = 0;
    for (size_t i = 0; i < s->n; i++)
        count += s->kind[i] == kind;
    return count;
}

static void steps(mps2p_solver *solver, int count)
{
    for (int k = 0; k < count; k++)
        MUST(mps2p_solver_step(solver));
}

/* Rewrites the root attribute fluid_out and reseals the file, as a crafted
 * file would. */
static void set_fluid_out(const char *path, uint64_t value)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t attribute = H5Aopen(file, "fluid_out", H5P_DEFAULT);
    CHECK(H5Awrite(attribute, H5T_NATIVE_UINT64, &value) >= 0, "cannot edit fluid_out");
    H5Aclose(attribute);
    H5Fclose(file);
    CHECK(reseal_file(path) == 0, "cannot reseal %s", path);
}

int main(void)
{
    char dir[] = "/tmp/mps2p-fluid-out-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    char path[256];
    snprintf(path, sizeof path, "%s/out.chk", dir);

    size_t a;
    mps2p_scene *scene = spray_scene(&a);
    const size_t b = a + 1, c = a + 2;
    MUST(mps2p_scene_set_param(scene, "out_limit", 0.05)); /* 10 of the 203 may leave */
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    mps2p_state *start;
    MUST(mps2p_solver_save_state(solver, &start));

    /* 1. the droplets leave one after another; the run goes on */
    snapshot s = take(solver);
    CHECK(s.density[b] > 0.0, "droplets a and b are not neighbours at the start (n_b = %g)",
          s.density[b]);
    release(&s);
    int b_alone = 0, k = 0, a_was_out = 0;
    double out = 0.0;
    for (; k < 400 && out < 3.0; k++) {
        int status = mps2p_solver_step(solver);
        CHECK(status == MPS2P_OK, "step %d: %s: %s", k + 1, mps2p_status_string(status),
              mps2p_solver_last_error(solver));
        if (status != MPS2P_OK)
            return check_summary("test_fluid_out");
        s = take(solver);
        out = s.fluid_out;
        CHECK(out == (double)count_kind(&s, MPS2P_KIND_OUT), "fluid_out %g, %zu of kind OUT",
              out, count_kind(&s, MPS2P_KIND_OUT));
        /* a out of the run for a whole step (the step it left in counted it
         * still), b still in it and within a's density radius: b has no
         * neighbour */
        if (a_was_out && s.kind[b] == MPS2P_KIND_FLUID) {
            double d = hypot(s.position[2 * a] - s.position[2 * b],
                             s.position[2 * a + 1] - s.position[2 * b + 1]);
            CHECK(d < 2.1 * 0.01, "a and b %g m apart", d);
            CHECK(s.density[b] == 0.0, "b sees the droplet out of the run: n = %g", s.density[b]);
            b_alone++;
        }
        a_was_out = s.kind[a] == MPS2P_KIND_OUT;
        release(&s);
    }
    CHECK(out == 3.0, "after %d steps %g droplets left", k, out);
    CHECK(b_alone > 0, "no step had a out of the run and b still in it");
    s = take(solver);
    for (size_t i = 0; i < s.n; i++) {
        int droplet = i == a || i == b || i == c;
        CHECK((s.kind[i] == MPS2P_KIND_OUT) == droplet, "particle %zu is of kind %d", i,
              s.kind[i]);
        if (!droplet)
            continue;
        CHECK(s.fluid_id[i] == 0, "droplet %zu lost its fluid id: %d", i, s.fluid_id[i]);
        CHECK(s.velocity[2 * i] == 0.0 && s.velocity[2 * i + 1] == 0.0 && s.pressure[i] == 0.0 &&
                  s.density[i] == 0.0,
              "droplet %zu: velocity (%g, %g), p = %g, n = %g", i, s.velocity[2 * i],
              s.velocity[2 * i + 1], s.pressure[i], s.density[i]);
        CHECK(s.position[2 * i + 1] > 0.35, "droplet %zu out of the run at y = %g, inside",
              i, s.position[2 * i + 1]);
    }
    printf("3 droplets out of the run after %llu steps, t = %.4f s (b had no neighbour for "
           "%d steps)\n", (unsigned long long)s.steps, s.time, b_alone);

    /* 2. frozen while the rest steps; a checkpoint restarts bit for bit */
    MUST(mps2p_solver_save_checkpoint(solver, path));
    steps(solver, AFTER);
    snapshot later = take(solver);
    size_t moved = 0;
    for (size_t i = 0; i < s.n; i++) {
        int changed = later.position[2 * i] != s.position[2 * i] ||
                      later.position[2 * i + 1] != s.position[2 * i + 1];
        if (later.kind[i] == MPS2P_KIND_OUT)
            CHECK(!changed && later.velocity[2 * i] == 0.0 && later.pressure[i] == 0.0,
                  "droplet %zu moved or took a velocity or pressure out of the run", i);
        else if (later.kind[i] == MPS2P_KIND_FLUID)
            moved += (size_t)changed;
    }
    CHECK(moved == count_kind(&later, MPS2P_KIND_FLUID) && moved == 200,
          "%zu of the column's 200 particles moved in %d steps", moved, AFTER);
    CHECK(later.fluid_out == 3.0 && later.time > s.time, "fluid_out %g, time %g after %g",
          later.fluid_out, later.time, s.time);
    mps2p_solver *restored;
    MUST(mps2p_solver_load_checkpoint(path, &restored));
    snapshot loaded = take(restored);
    CHECK(same(&loaded, &s), "the loaded solver is not the saved one (kinds, fluid_out %g)",
          loaded.fluid_out);
    steps(restored, AFTER);
    snapshot again = take(restored);
    CHECK(same(&again, &later), "the restart is not bitwise the run it was saved from");
    release(&loaded);
    release(&again);
    mps2p_solver_destroy(restored);

    /* 3. a saved state from before puts the droplets back in the run: the same run again */
    MUST(mps2p_solver_restore_state(solver, start));
    snapshot back = take(solver);
    CHECK(back.fluid_out == 0.0 && count_kind(&back, MPS2P_KIND_OUT) == 0,
          "restored from the start: fluid_out %g, %zu of kind OUT", back.fluid_out,
          count_kind(&back, MPS2P_KIND_OUT));
    release(&back);
    steps(solver, (int)later.steps);
    again = take(solver);
    CHECK(same(&again, &later), "the run from the restored start differs");
    release(&again);

    /* 4. a fluid_out that is not the count of its kinds is refused */
    set_fluid_out(path, 2);
    mps2p_solver *refused = NULL;
    int status = mps2p_solver_load_checkpoint(path, &refused);
    CHECK(status == MPS2P_ERR_IO && !refused && strstr(mps2p_last_error(), "fluid_out"),
          "fluid_out 2 with 3 out: %s: %s", mps2p_status_string(status), mps2p_last_error());
    mps2p_solver_destroy(refused);

    release(&s);
    release(&later);
    mps2p_state_destroy(start);
    mps2p_solver_destroy(solver);
    remove(path);
    CHECK(rmdir(dir) == 0, "%s is not empty", dir);
    return check_summary("test_fluid_out");
}

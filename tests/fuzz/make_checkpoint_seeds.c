/* Writes the checkpoint fuzzer's seeds: small real checkpoints (a few
 * dozen particles) with each pressure solver and option, one diverged-free
 * run after some steps, and a two-phase one (group two_phase), into the
 * directory given. Run by hand when the format changes:
 * build-fuzz/tests/fuzz/make_checkpoint_seeds DIR. The corpus keeps, as
 * format3-*.chk, the same seeds written by the library before format 4
 * (no checksum header), which cover reading older files. */
#include <mps2p.h>

#include <stdio.h>

static int make(const char *dir, const char *name, const char *solver_name, int steps,
                int closed, int with_air)
{
    mps2p_scene *scene;
    mps2p_solver *solver;
    int water, air, status;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if ((status = mps2p_scene_create(0.05, &scene)) != MPS2P_OK)
        return status;
    status = mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water);
    if (!status)
        status = mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.15, 0.1);
    /* air beside and above the water: effect two_phase on */
    if (!status && with_air)
        status = mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air);
    if (!status && with_air)
        status = mps2p_scene_add_fluid_box(scene, air, 0.15, 0, 0.25, 0.15);
    if (!status && with_air)
        status = mps2p_scene_add_fluid_box(scene, air, 0, 0.1, 0.15, 0.15);
    if (!status)
        status = mps2p_scene_add_tank(scene, 0, 0, 0.25, 0.2, !closed);
    if (!status)
        status = mps2p_scene_set_option(scene, "pressure_solver", solver_name);
    if (!status)
        status = mps2p_scene_set_param(scene, "re_laplacian", 2.1);
    if (!status)
        status = mps2p_solver_create(scene, &solver);
    mps2p_scene_destroy(scene);
    for (int k = 0; !status && k < steps; k++)
        status = mps2p_solver_step(solver);
    if (!status)
        status = mps2p_solver_save_checkpoint(solver, path);
    if (status)
        fprintf(stderr, "%s: %s\n", name, mps2p_last_error());
    else
        mps2p_solver_destroy(solver);
    return status;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: make_checkpoint_seeds DIR\n");
        return 2;
    }
    return make(argv[1], "cholmod-start.chk", "cholmod", 0, 0, 0) ||
           make(argv[1], "cholmod-5-steps.chk", "cholmod", 5, 0, 0) ||
           make(argv[1], "cg-3-steps.chk", "cg", 3, 1, 0) ||
           make(argv[1], "two-phase-3-steps.chk", "cg", 3, 1, 1);
}

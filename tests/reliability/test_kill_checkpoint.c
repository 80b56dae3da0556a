/* Atomic checkpoints: a child process runs a small dam break and saves a
 * checkpoint to the same path after every step, continuing from that
 * checkpoint when it exists; the parent kills it with SIGKILL after a random
 * delay, many times. After every kill the checkpoint on disk must load and
 * step, and its step count must never go backwards. A kill may leave
 * "<path>.tmp" behind (the next save truncates it); never a half-written
 * checkpoint under the real name. MPS2P_KILL_SEED fixes the random delays. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "../scenes.h"

#define KILLS 40

static void child(const char *path)
{
    mps2p_solver *solver = NULL;
    if (access(path, F_OK) == 0) {
        if (mps2p_solver_load_checkpoint(path, &solver) != MPS2P_OK)
            _exit(3);
    } else {
        mps2p_scene *scene = dam_break_scene(0.02);
        if (mps2p_solver_create(scene, &solver) != MPS2P_OK)
            _exit(4);
        mps2p_scene_destroy(scene);
    }
    for (;;) {
        if (mps2p_solver_step(solver) != MPS2P_OK)
            _exit(5);
        if (mps2p_solver_save_checkpoint(solver, path) != MPS2P_OK)
            _exit(6);
    }
}

int main(void)
{
    const char *seed_text = getenv("MPS2P_KILL_SEED");
    unsigned seed = seed_text ? (unsigned)strtoul(seed_text, NULL, 10)
                              : (unsigned)time(NULL) ^ (unsigned)getpid();
    srand(seed);
    char dir[] = "/tmp/mps2p-kill-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    char path[256], temporary[300];
    snprintf(path, sizeof path, "%s/run.chk", dir);
    snprintf(temporary, sizeof temporary, "%s.tmp", path);

    uint64_t last_steps = 0;
    int loads = 0, leftovers = 0;
    for (int k = 0; k < KILLS; k++) {
        fflush(NULL);
        pid_t pid = fork();
        if (pid < 0) {
            perror("fork");
            return 1;
        }
        if (pid == 0)
            child(path);
        /* 10 to 250 ms: through library start, steps, writes and renames */
        long delay_us = 10000 + rand() % 240000;
        struct timespec delay = {0, delay_us * 1000};
        nanosleep(&delay, NULL);
        kill(pid, SIGKILL);
        int wstatus = 0;
        waitpid(pid, &wstatus, 0);
        CHECK(WIFSIGNALED(wstatus) && WTERMSIG(wstatus) == SIGKILL,
              "kill %d: the child ended by itself (exit status %d) instead of being killed",
              k, WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1);
        leftovers += access(temporary, F_OK) == 0;
        if (access(path, F_OK) != 0)
            continue; /* killed before its first save */
        mps2p_solver *solver = NULL;
        int status = mps2p_solver_load_checkpoint(path, &solver);
        CHECK(status == MPS2P_OK, "kill %d after %ld us: the checkpoint does not load: %s", k,
              delay_us, mps2p_last_error());
        if (status != MPS2P_OK)
            break;
        uint64_t steps = 0;
        MUST(mps2p_solver_get_step_count(solver, &steps));
        CHECK(steps >= last_steps, "kill %d: checkpoint went back from step %llu to %llu", k,
              (unsigned long long)last_steps, (unsigned long long)steps);
        last_steps = steps;
        status = mps2p_solver_step(solver);
        CHECK(status == MPS2P_OK, "kill %d: the loaded checkpoint does not step: %s", k,
              mps2p_last_error());
        mps2p_solver_destroy(solver);
        loads++;
    }
    CHECK(loads >= KILLS / 2, "only %d of %d kills left a checkpoint", loads, KILLS);
    CHECK(last_steps > 0, "no steps were checkpointed");
    printf("test_kill_checkpoint: seed %u, %d kills, %d checkpoints loaded and stepped, "
           "last at step %llu, %d kills left a .tmp behind\n", seed, KILLS, loads,
           (unsigned long long)last_steps, leftovers);
    remove(temporary);
    remove(path);
    rmdir(dir);
    return check_summary("test_kill_checkpoint");
}

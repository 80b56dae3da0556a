/* The memory a scene or a solver may take (parameter memory_limit, or what
 * the system gives the process), and what one is estimated to take: checked
 * before allocating. */
#define _POSIX_C_SOURCE 200809L
#include "core/core.h"
#include "numerics/numerics.h"

#include <math.h>
#include <stdio.h>
#include <sys/resource.h>
#include <unistd.h>

/* A byte count from a cgroup file ("max" or missing: no limit). */
static double cgroup_limit(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return INFINITY;
    unsigned long long bytes = 0;
    int got = fscanf(f, "%llu", &bytes);
    fclose(f);
    return got == 1 && bytes > 0 ? (double)bytes : INFINITY;
}

double memory_available(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double bytes = pages > 0 && page > 0 ? (double)pages * (double)page : INFINITY;
    const int limits[] = {RLIMIT_AS, RLIMIT_DATA};
    for (size_t k = 0; k < sizeof limits / sizeof limits[0]; k++) {
        struct rlimit r;
        if (getrlimit(limits[k], &r) == 0 && r.rlim_cur != RLIM_INFINITY)
            bytes = fmin(bytes, (double)r.rlim_cur);
    }
    bytes = fmin(bytes, cgroup_limit("/sys/fs/cgroup/memory.max"));
    bytes = fmin(bytes, cgroup_limit("/sys/fs/cgroup/memory/memory.limit_in_bytes"));
    return bytes;
}

double memory_limit_bytes(const params *p)
{
    return p->memory_limit > 0.0 ? p->memory_limit : memory_available();
}

size_t scene_bytes_per_particle(void)
{
    const mps2p_scene *scene = NULL;
    return 2 * sizeof *scene->position + 2 * sizeof *scene->velocity + sizeof *scene->kind +
           sizeof *scene->fluid_id + sizeof *scene->body_id;
}

double solver_bytes_estimate(const params *p, size_t n)
{
    size_t per_particle = 0; /* the arrays of creation, and their copies from before a step */
    for (size_t k = 0; k < solver_fields.count; k++) {
        const field *f = &solver_fields.rows[k];
        if ((f->flags & FIELD_PER_PARTICLE) && !(f->flags & FIELD_ON_DEMAND))
            per_particle += field_bytes(f, 1) * (f->flags & FIELD_ROLLED_BACK ? 2 : 1);
    }
    const double arrays = (double)per_particle;
    /* lattice sites within the list's cutoff and the short list's: pi r^2, a
     * 4-byte index each (numerics.h); the two row starts, the build's
     * positions and the particle's slot in the cell grid */
    const double skin = p->neighbour_skin, pi = 3.14159265358979;
    const double cutoff = params_max_radius(p) + skin, near = p->re_density + skin;
    const double pairs = pi * (cutoff * cutoff + near * near);
    const double list_indices = pairs * sizeof(uint32_t);
    const double list = list_indices + 2 * sizeof(size_t) + 2 * sizeof(double) + sizeof(uint32_t);
    /* the pressure matrix, every particle an unknown: its pairs within
     * re_laplacian and the diagonal, an int column and a double value each */
    const double matrix_entries =
        pi * p->re_laplacian * p->re_laplacian * (sizeof(int) + sizeof(double));
    const double matrix = matrix_entries + sizeof(int) + sizeof(double) + sizeof(int);
    /* with a team, each thread's run of the list or of the matrix but the
     * first is built in room of its own and then copied in (and freed: the
     * two are never held at once): up to (threads - 1) / threads of the
     * larger held twice */
    const int team = team_size(p->threads);
    const double staged = (double)(team - 1) / team * fmax(list_indices, matrix_entries);
    return (double)n * (arrays + list + matrix + staged);
}

int memory_check(const params *p, double bytes, const char *what, char *handle_error)
{
    const double limit = memory_limit_bytes(p);
    if (bytes <= limit)
        return MPS2P_OK;
    return fail(handle_error, MPS2P_ERR_NOMEM,
                "%s would take %.3g bytes, more than the memory limit of %.3g bytes "
                "(parameter memory_limit%s)", what, bytes, limit,
                p->memory_limit > 0.0 ? ""
                                      : " = 0: the memory the system gives this process; "
                                        "set memory_limit to allow more");
}

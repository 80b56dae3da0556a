// A C++ host's progress callback that throws: the exception reaches the
// host, and the solver is not left inside mps2p_solver_advance_to (every
// later call refused, destroy freeing nothing): it steps on, and a destroy
// asked for before the throw is done (valgrind or ASan see no leak).
#include <mps2p.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

static int failures = 0;
#define EXPECT(condition)                                                        \
    do {                                                                         \
        if (!(condition)) {                                                      \
            std::fprintf(stderr, "FAIL %s:%d: %s (%s)\n", __FILE__, __LINE__,    \
                         #condition, mps2p_last_error());                        \
            failures++;                                                          \
        }                                                                        \
    } while (0)

static mps2p_solver *small_dam_break()
{
    mps2p_scene *scene = nullptr;
    mps2p_solver *solver = nullptr;
    int water = 0;
    if (mps2p_scene_create(0.02, &scene) || mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water) ||
        mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.2) ||
        mps2p_scene_add_tank(scene, 0.0, 0.0, 0.4, 0.3, 1) || mps2p_solver_create(scene, &solver)) {
        std::fprintf(stderr, "FAIL: building the scene: %s\n", mps2p_last_error());
        std::exit(1);
    }
    mps2p_scene_destroy(scene);
    return solver;
}

struct calls {
    int count = 0;
    bool destroy_first = false;
};

static int throw_on_third(const mps2p_solver *solver, void *data)
{
    calls *c = static_cast<calls *>(data);
    if (++c->count < 3)
        return 0;
    if (c->destroy_first)
        mps2p_solver_destroy(const_cast<mps2p_solver *>(solver));
    throw std::runtime_error("the host's own failure");
}

int main()
{
    mps2p_solver *solver = small_dam_break();
    calls c;
    bool caught = false;
    try {
        mps2p_solver_advance_to(solver, 0.1, throw_on_third, &c);
    } catch (const std::runtime_error &) {
        caught = true;
    }
    EXPECT(caught && c.count == 3);
    uint64_t steps = 0;
    EXPECT(mps2p_solver_get_step_count(solver, &steps) == MPS2P_OK && steps == 3);
    EXPECT(mps2p_solver_step(solver) == MPS2P_OK);
    double time = 0.0;
    EXPECT(mps2p_solver_advance_to(solver, 0.02, nullptr, nullptr) == MPS2P_OK);
    EXPECT(mps2p_solver_get_time(solver, &time) == MPS2P_OK && time == 0.02);
    mps2p_solver_destroy(solver);

    // destroyed from inside, then thrown: freed as the exception leaves (a
    // leak here shows in the sanitizer builds of scripts/test.sh)
    solver = small_dam_break();
    calls d;
    d.destroy_first = true;
    caught = false;
    try {
        mps2p_solver_advance_to(solver, 0.1, throw_on_third, &d);
    } catch (const std::runtime_error &) {
        caught = true;
    }
    EXPECT(caught && d.count == 3);
    if (failures)
        return 1;
    std::printf("test_throwing_callback: all checks passed\n");
    return 0;
}

/* pressure_solver "gamg": PETSc's conjugate gradients preconditioned by its
 * smoothed-aggregation algebraic multigrid (KSPCG + PCGAMG), built only with
 * option petsc (meson_options.txt).
 *
 * PETSc is initialised once per process (pthread_once), on MPI_COMM_SELF,
 * without signal handlers or option files, its errors returned as codes
 * (PetscReturnErrorHandler), never printed. PETSc 3.18 as Debian builds it is
 * not thread-safe (no --with-threadsafety: its logging, object registry and
 * options database are process-wide), so every PETSc call below holds
 * petsc_lock: two solvers in two threads take turns in their gamg solves.
 *
 * Each solve builds a fresh KSP and hierarchy from the matrix alone: the
 * result is a function of (A, b, initial guess), not of earlier steps, so a
 * restored checkpoint continues bit for bit. PETSc's loops are serial here
 * (no OpenMP in its build, and parameter threads does not reach it): the same
 * bits for any thread count. */
#include "numerics/numerics.h"

#include <math.h>
#include <petscksp.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The matrix is handed over without a copy: its int indices must be PetscInt. */
_Static_assert(sizeof(PetscInt) == sizeof(int), "PETSc with 64-bit indices");
_Static_assert(sizeof(PetscScalar) == sizeof(double), "PETSc with complex or single scalars");

struct gamg_solver {
    size_t hierarchy_bytes; /* the multigrid hierarchy of the last solve (estimate) */
};

static pthread_once_t petsc_once = PTHREAD_ONCE_INIT;
static PetscErrorCode petsc_init_error; /* written once, inside petsc_once */
static pthread_mutex_t petsc_lock = PTHREAD_MUTEX_INITIALIZER;

static void petsc_init(void)
{
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
        /* serialised calls from any thread is what petsc_lock gives */
        int provided;
        if (MPI_Init_thread(NULL, NULL, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) {
            petsc_init_error = PETSC_ERR_LIB;
            return;
        }
    }
    /* one process, whatever the host does with MPI */
    PETSC_COMM_WORLD = MPI_COMM_SELF;
    /* no signal handlers; ~/.petscrc and ./.petscrc are not read */
    static char name[] = "libmps2p", no_signals[] = "-no_signal_handler",
                no_rc[] = "-skip_petscrc";
    static char *arguments[] = {name, no_signals, no_rc, NULL};
    int argc = 3;
    char **argv = arguments;
    petsc_init_error = PetscInitialize(&argc, &argv, NULL, NULL);
    if (petsc_init_error == 0)
        petsc_init_error = PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
}

static int status_of(PetscErrorCode code)
{
    return code == PETSC_ERR_MEM ? MPS2P_ERR_NOMEM : MPS2P_ERR_SOLVE;
}

static int petsc_failed(PetscErrorCode code, const char *what, char *message, size_t size)
{
    const char *text = NULL;
    PetscErrorMessage(code, &text, NULL);
    snprintf(message, size, "gamg: %s failed: PETSc error %d (%s)", what, (int)code,
             text ? text : "unknown");
    return status_of(code);
}

int gamg_create(gamg_solver **out, char *message, size_t size)
{
    pthread_once(&petsc_once, petsc_init);
    if (petsc_init_error)
        return petsc_failed(petsc_init_error, "PetscInitialize", message, size);
    gamg_solver *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(message, size, "out of memory starting the gamg solver");
        return MPS2P_ERR_NOMEM;
    }
    *out = g;
    return MPS2P_OK;
}

void gamg_destroy(gamg_solver *g)
{
    free(g);
}

size_t gamg_memory(const gamg_solver *g)
{
    return g ? sizeof *g + g->hierarchy_bytes : 0;
}

/* Bytes of an AIJ matrix of PETSc's: values and column indices of its
 * allocated entries, row offsets and lengths. */
static size_t matrix_bytes(Mat m)
{
    MatInfo info;
    PetscInt rows, columns;
    if (MatGetInfo(m, MAT_LOCAL, &info) || MatGetSize(m, &rows, &columns))
        return 0;
    return (size_t)info.nz_allocated * (sizeof(PetscScalar) + sizeof(PetscInt)) +
           (size_t)(rows + 1) * 3 * sizeof(PetscInt);
}

/* An estimate of what the hierarchy holds beyond A itself: each coarse
 * level's operator, each interpolation, and about ten vectors a level (the
 * multigrid's and the Chebyshev smoothers' work vectors). */
static size_t hierarchy_bytes(KSP ksp, size_t rows)
{
    PC pc;
    PetscInt levels = 0;
    if (KSPGetPC(ksp, &pc) || PCMGGetLevels(pc, &levels))
        return 0;
    size_t bytes = 10 * rows * sizeof(PetscScalar); /* the finest level's vectors */
    for (PetscInt level = 0; level + 1 < levels; level++) {
        KSP smoother;
        Mat op;
        PetscInt level_rows, level_columns;
        if (PCMGGetSmoother(pc, level, &smoother) || KSPGetOperators(smoother, &op, NULL) ||
            MatGetSize(op, &level_rows, &level_columns))
            continue;
        bytes += matrix_bytes(op) + 10 * (size_t)level_rows * sizeof(PetscScalar);
    }
    for (PetscInt level = 1; level < levels; level++) {
        Mat interpolation;
        if (PCMGGetInterpolation(pc, level, &interpolation) == 0)
            bytes += matrix_bytes(interpolation);
    }
    return bytes;
}

/* Under petsc_lock. The vectors wrap b and x, the matrix A's arrays: no copies. */
static int solve_locked(gamg_solver *g, const sparse_matrix *a, const double *b, double *x,
                        double tolerance, size_t max_iterations, size_t *iterations,
                        char *message, size_t size)
{
    const PetscInt n = a->rows;
    Mat matrix = NULL;
    Vec rhs = NULL, solution = NULL;
    KSP ksp = NULL;
    PC pc;
    PetscErrorCode code;
    const char *what = "matrix";
    /* PETSc counts iterations in a PetscInt */
    PetscInt limit = max_iterations > (size_t)PETSC_MAX_INT ? PETSC_MAX_INT
                                                             : (PetscInt)max_iterations;
    int status = MPS2P_OK;
    if ((code = MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, n, n, a->row_start, a->column,
                                          a->value, &matrix)))
        goto failed;
    what = "matrix options";
    if ((code = MatSetOption(matrix, MAT_SPD, PETSC_TRUE)) ||
        (code = MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE)))
        goto failed;
    what = "vectors";
    if ((code = VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, b, &rhs)) ||
        (code = VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, x, &solution)))
        goto failed;
    what = "KSP set-up";
    /* |b - A x| <= tolerance |b|, as the library's own CG; no absolute test.
     * No KSPSetFromOptions: PETSc's options database (PETSC_OPTIONS) does not
     * change the solver, and the prefix keeps it from the inner solvers too. */
    if ((code = KSPCreate(PETSC_COMM_SELF, &ksp)) ||
        (code = KSPSetOptionsPrefix(ksp, "mps2p_")) ||
        (code = KSPSetOperators(ksp, matrix, matrix)) || (code = KSPSetType(ksp, KSPCG)) ||
        (code = KSPGetPC(ksp, &pc)) || (code = PCSetType(pc, PCGAMG)) ||
        (code = KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED)) ||
        (code = KSPSetTolerances(ksp, tolerance, 0.0, PETSC_DEFAULT, limit)) ||
        (code = KSPSetInitialGuessNonzero(ksp, PETSC_TRUE)))
        goto failed;
    what = "multigrid set-up";
    if ((code = KSPSetUp(ksp)))
        goto failed;
    g->hierarchy_bytes = hierarchy_bytes(ksp, (size_t)n);
    what = "KSPSolve";
    if ((code = KSPSolve(ksp, rhs, solution)))
        goto failed;
    KSPConvergedReason reason;
    PetscInt done = 0;
    PetscReal norm = 0.0;
    if ((code = KSPGetConvergedReason(ksp, &reason)) ||
        (code = KSPGetIterationNumber(ksp, &done)) || (code = KSPGetResidualNorm(ksp, &norm)))
        goto failed;
    *iterations = (size_t)done;
    if (reason < 0) {
        double b_norm = 0.0;
        for (PetscInt i = 0; i < n; i++)
            b_norm += b[i] * b[i];
        snprintf(message, size,
                 "gamg did not converge: %s after %d iterations, residual %g of |b|, "
                 "tolerance %g",
                 KSPConvergedReasons[reason], (int)done, (double)norm / sqrt(b_norm),
                 tolerance);
        status = MPS2P_ERR_SOLVE;
    }
    goto done;
failed:
    status = petsc_failed(code, what, message, size);
done:
    KSPDestroy(&ksp);
    VecDestroy(&solution);
    VecDestroy(&rhs);
    MatDestroy(&matrix);
    return status;
}

int gamg_solve(gamg_solver *g, const sparse_matrix *a, const double *b, double *x,
               double tolerance, size_t max_iterations, size_t *iterations, char *message,
               size_t size)
{
    *iterations = 0;
    /* b = 0: x = 0 (PETSc's relative test would have nothing to be relative to) */
    int zero = 1;
    for (int i = 0; i < a->rows && zero; i++)
        zero = b[i] == 0.0;
    if (zero) {
        memset(x, 0, (size_t)a->rows * sizeof *x);
        return MPS2P_OK;
    }
    pthread_mutex_lock(&petsc_lock);
    int status = solve_locked(g, a, b, x, tolerance, max_iterations, iterations, message, size);
    pthread_mutex_unlock(&petsc_lock);
    return status;
}

/* Every part's header, for the tests of internal stages (tests/test_operators.c,
 * tests/reliability/test_neighbours_nomem.c). The library's own files include
 * the headers of the parts they use, each part's one header (docs/internals.md). */
#ifndef MPS2P_INTERNAL_H
#define MPS2P_INTERNAL_H

#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"
#include "coupling/coupling.h"
#include "solver/solver.h"

#endif

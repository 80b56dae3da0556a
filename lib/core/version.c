/* Run-time version of the loaded library. */
#include "core/core.h"

unsigned mps2p_version_number(void)
{
    return MPS2P_VERSION_NUMBER;
}

const char *mps2p_version_string(void)
{
    return MPS2P_VERSION_STRING;
}

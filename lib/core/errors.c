/* Status names and error messages: per thread, and per handle. */
#include "core/core.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* Thread-local, so threads never see each other's messages. */
static _Thread_local char thread_error[ERROR_MESSAGE_SIZE];

int fail(char *handle_buffer, int status, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(thread_error, sizeof thread_error, format, args);
    va_end(args);
    if (handle_buffer)
        memcpy(handle_buffer, thread_error, ERROR_MESSAGE_SIZE);
    return status;
}

void error_clear(void)
{
    thread_error[0] = '\0';
}

const char *mps2p_last_error(void)
{
    return thread_error;
}

const char *mps2p_status_string(int status)
{
    switch (status) {
    case MPS2P_OK: return "MPS2P_OK";
    case MPS2P_STOPPED: return "MPS2P_STOPPED";
    case MPS2P_ERR_NULL: return "MPS2P_ERR_NULL";
    case MPS2P_ERR_INVALID: return "MPS2P_ERR_INVALID";
    case MPS2P_ERR_UNKNOWN_KEY: return "MPS2P_ERR_UNKNOWN_KEY";
    case MPS2P_ERR_NOMEM: return "MPS2P_ERR_NOMEM";
    case MPS2P_ERR_STATE: return "MPS2P_ERR_STATE";
    case MPS2P_ERR_BUFFER: return "MPS2P_ERR_BUFFER";
    case MPS2P_ERR_SOLVE: return "MPS2P_ERR_SOLVE";
    case MPS2P_ERR_DIVERGED: return "MPS2P_ERR_DIVERGED";
    case MPS2P_ERR_IO: return "MPS2P_ERR_IO";
    default: return "MPS2P_ERR_UNRECOGNISED_STATUS";
    }
}

#include "negobs/status.h"

const char *negobs_status_str(negobs_status_t status)
{
#ifdef NEGOBS_NO_ERRSTR
    (void)status;
    return "";
#else
    switch (status) {
    case NEGOBS_OK: return "ok";
    case NEGOBS_ERR_INVAL: return "invalid argument";
    case NEGOBS_ERR_NOSPACE: return "not enough space";
    case NEGOBS_ERR_RANGE: return "value out of range";
    case NEGOBS_ERR_UNSUPPORTED: return "not supported";
    case NEGOBS_ERR_IO: return "I/O error";
    case NEGOBS_ERR_TIMEOUT: return "timed out";
    case NEGOBS_ERR_AGAIN: return "try again";
    case NEGOBS_ERR_NODEV: return "no such device";
    case NEGOBS_ERR_ALIGN: return "workspace misaligned";
    case NEGOBS_ERR_CORRUPT: return "memory guard or checksum corrupted";
    case NEGOBS_ERR_STATE: return "call out of order";
    }
    return "unknown status";
#endif
}

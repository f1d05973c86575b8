#include "negobs/version.h"

const char *negobs_version(void)
{
    return NEGOBS_VERSION_STRING;
}

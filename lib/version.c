/* meristem — library version. */
#include "config.h"

#include <meristem/version.h>

const char *mer_version(void)
{
    return PACKAGE_VERSION;
}

/* meristem — the 3-vector helpers live in core/vec.h; this name stays for the files
 * that include it by it. Not installed. */
#ifndef MERISTEM_VEC_PRIVATE_H
#define MERISTEM_VEC_PRIVATE_H
#include "core/vec.h"
#endif

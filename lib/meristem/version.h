/* meristem — library version. */
#ifndef MERISTEM_VERSION_H
#define MERISTEM_VERSION_H

#ifdef __cplusplus
extern "C" {
#endif

/* The package version this library was built as, e.g. "0.1.0". Static storage. */
const char *mer_version(void);

#ifdef __cplusplus
}
#endif

#endif

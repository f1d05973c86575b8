/* negobs library version. */
#ifndef NEGOBS_VERSION_H
#define NEGOBS_VERSION_H

#ifdef __cplusplus
extern "C" {
#endif

#define NEGOBS_VERSION_MAJOR 0
#define NEGOBS_VERSION_MINOR 1
#define NEGOBS_VERSION_PATCH 0
#define NEGOBS_VERSION_STRING "0.1.0"

/** @brief Version of the linked library, e.g. "0.1.0". */
const char *negobs_version(void);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_VERSION_H */

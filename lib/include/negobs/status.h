/*
 * negobs status codes.
 *
 * One enum is shared by lib/ and port/. Zero is success and every error is
 * negative, so functions that return counts can use non-negative values.
 * Numbers are stable: new codes are appended, never renumbered.
 */
#ifndef NEGOBS_STATUS_H
#define NEGOBS_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum negobs_status {
    NEGOBS_OK = 0,
    NEGOBS_ERR_INVAL = -1,       /**< bad argument, config or image   */
    NEGOBS_ERR_NOSPACE = -2,     /**< workspace or buffer too small   */
    NEGOBS_ERR_RANGE = -3,       /**< value not representable         */
    NEGOBS_ERR_UNSUPPORTED = -4, /**< valid request, not built/implemented */
    NEGOBS_ERR_IO = -5,          /**< port: device or file I/O        */
    NEGOBS_ERR_TIMEOUT = -6,     /**< port: nothing arrived in time   */
    NEGOBS_ERR_AGAIN = -7,       /**< port: try again                 */
    NEGOBS_ERR_NODEV = -8,       /**< port: device absent or lost     */
    NEGOBS_ERR_ALIGN = -9,       /**< workspace not 16-byte aligned   */
    NEGOBS_ERR_CORRUPT = -10,    /**< guard canary or checksum broken */
    NEGOBS_ERR_STATE = -11       /**< call out of order (e.g. no init) */
} negobs_status_t;

/**
 * @brief Short English description of a status code.
 * @return A static string; "unknown status" for values not in the enum.
 *         Returns "" when the library is built with NEGOBS_NO_ERRSTR.
 */
const char *negobs_status_str(negobs_status_t status);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_STATUS_H */

/*
 * The libcamera source's pairing step (pure, so that it can be driven by
 * a fake pair of cameras in tests/port/test_libcamera_pair.c).
 */
#include "negobs_port/camera_libcamera.h"

negobs_lc_step_t negobs_libcamera_pair_step(int32_t nsides, bool pend_l,
                                            uint64_t ts_l, bool pend_r,
                                            uint64_t ts_r, uint64_t tol_ns)
{
    if (nsides == 1) {
        return pend_l ? NEGOBS_LC_SINGLE : NEGOBS_LC_WAIT;
    }
    if (nsides != 2 || !pend_l || !pend_r) {
        return NEGOBS_LC_WAIT;
    }
    switch (negobs_pair_decide(ts_l, ts_r, tol_ns)) {
    case NEGOBS_PAIR_MATCH: return NEGOBS_LC_PAIR;
    case NEGOBS_PAIR_DROP_LEFT: return NEGOBS_LC_DROP_LEFT;
    default: return NEGOBS_LC_DROP_RIGHT;
    }
}

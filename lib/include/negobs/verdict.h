/*
 * The verdict the detector hands to the alert logic: what the frame says
 * (clear, hazard, or no information) and how urgent it is. Its own header
 * so the alert logic does not depend on the detector's interface.
 */
#ifndef NEGOBS_VERDICT_H
#define NEGOBS_VERDICT_H

#ifdef __cplusplus
extern "C" {
#endif

/** Urgency of a hazard (and of the alert it raises). */
typedef enum negobs_alert_level {
    NEGOBS_LEVEL_NONE = 0,
    NEGOBS_LEVEL_CAUTION = 1,
    NEGOBS_LEVEL_IMMINENT = 2
} negobs_alert_level_t;

/** What one frame says about the path ahead. */
typedef enum negobs_detect_state {
    NEGOBS_DETECT_CLEAR = 0,  /**< checked and clear                 */
    NEGOBS_DETECT_HAZARD = 1, /**< at least one confirmed/held hazard */
    NEGOBS_DETECT_NO_INFO = 2 /**< degraded: see reasons             */
} negobs_detect_state_t;

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_VERDICT_H */

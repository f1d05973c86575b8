/*
 * Camera discovery (negobs_run --list-cameras) and the V4L2 format choice
 * that uses the same enumeration.
 *
 * V4L2: every /dev/video* node (or the nodes given) is opened and asked
 * VIDIOC_QUERYCAP, VIDIOC_ENUM_FMT, VIDIOC_ENUM_FRAMESIZES and
 * VIDIOC_ENUM_FRAMEINTERVALS, and printed like `v4l2-ctl
 * --list-formats-ext`, each format marked with whether negobs can use it.
 * libcamera: every camera the camera manager lists, with the pixel formats
 * and sizes of a video-recording stream, like `cam -l` and `cam --list-properties`.
 */
#ifndef NEGOBS_PORT_CAMERA_LIST_H
#define NEGOBS_PORT_CAMERA_LIST_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One size of one format, with its fastest rate. */
typedef struct negobs_v4l2_mode {
    uint32_t fourcc;
    int32_t width;
    int32_t height;
    uint32_t fps_milli; /**< fastest rate, 1/1000 fps; 0 = not said */
} negobs_v4l2_mode_t;

/** Modes kept per node (a UVC camera lists some 10 formats x 20 sizes). */
#define NEGOBS_V4L2_MAX_MODES 256

/**
 * @brief Choose the pixel format for a capture of w x h at fps from the
 *        modes a node lists (pure).
 *        1. the best-ranked usable format listing w x h at >= fps;
 *        2. else, among usable formats listing w x h, the fastest (then
 *           the best-ranked): a UVC camera sends 2560x720 YUYV at 5 fps
 *           but MJPEG at 30, and a late frame is worse than a decode;
 *        3. else the best-ranked usable format (the driver then picks the
 *           nearest size at S_FMT).
 * @return the fourcc, 0 when no listed format is usable.
 */
uint32_t negobs_v4l2_choose_format(const negobs_v4l2_mode_t *modes, size_t n,
                                   int32_t width, int32_t height, int32_t fps);

/**
 * @brief Enumerate the modes of an open V4L2 node (ENUM_FMT,
 *        ENUM_FRAMESIZES, ENUM_FRAMEINTERVALS). A stepwise or continuous
 *        size range is kept as its largest size, plus w x h when the
 *        range holds it.
 * @return modes found (at most max); formats without any size listing
 *         give one mode of size 0 x 0.
 */
size_t negobs_v4l2_enum_modes(int fd, int32_t width, int32_t height,
                              negobs_v4l2_mode_t *modes, size_t max);

/**
 * @brief Print one V4L2 node (capabilities, formats, sizes, rates).
 * @return NEGOBS_OK when it offers a usable capture format;
 *         NEGOBS_ERR_NODEV (cannot open), NEGOBS_ERR_UNSUPPORTED (not a
 *         V4L2 capture device, or nothing usable: said in the output).
 */
negobs_status_t negobs_v4l2_list_node(const char *path, FILE *out);

/**
 * @brief Print every /dev/video* node in name order.
 * @return usable nodes found.
 */
int negobs_v4l2_list_all(FILE *out);

/**
 * @brief Print the cameras libcamera sees (formats and sizes).
 * @return usable cameras found; -1 when built without libcamera or its
 *         camera manager does not start (said in the output).
 */
int negobs_libcamera_list(FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_CAMERA_LIST_H */

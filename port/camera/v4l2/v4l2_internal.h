/*
 * Internal to the V4L2 backend (camera_v4l2.c, v4l2_dev.c): one capture
 * node's setup and teardown. Not installed; nothing outside
 * port/camera/v4l2 includes it.
 */
#ifndef NEGOBS_PORT_V4L2_INTERNAL_H
#define NEGOBS_PORT_V4L2_INTERNAL_H

#include <stdint.h>

#include "negobs_port/camera_v4l2.h"

/* Formats st->errmsg (printf-style), with ": strerror(err)" appended when
 * err != 0. */
void v4l2_error(negobs_v4l2_t *st, int err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* ioctl() again while interrupted by a signal. */
int v4l2_xioctl(int fd, unsigned long req, void *arg);

/* ENODEV/ENOENT/ENXIO: the device is gone; anything else: I/O. */
negobs_status_t v4l2_errno_status(int e);

/* A node holding nothing (fd -1, no buffers). */
void v4l2_dev_reset(negobs_v4l2_dev_t *d);

/* STREAMOFF, unmap and free the buffers, close; then reset. */
void v4l2_dev_close(negobs_v4l2_dev_t *d);

/* Open d->path, check it captures, negotiate the format, set the rate and
 * map the buffers; on failure the node is closed and errmsg says why. */
negobs_status_t v4l2_dev_open(negobs_v4l2_t *st, negobs_v4l2_dev_t *d);

/* Queue buffer idx again (VIDIOC_QBUF). */
negobs_status_t v4l2_dev_queue(negobs_v4l2_dev_t *d, uint32_t idx);

/* Queue every buffer and STREAMON. */
negobs_status_t v4l2_dev_start(negobs_v4l2_t *st, negobs_v4l2_dev_t *d);

/* Exposure and gain: set on both nodes alike, or on neither. */
void v4l2_apply_controls(negobs_v4l2_t *st);

#endif /* NEGOBS_PORT_V4L2_INTERNAL_H */

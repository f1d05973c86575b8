/* Recording on a writer thread; the policy is in negobs_port/record_queue.h. */
#define _POSIX_C_SOURCE 200809L

#include "negobs_port/record_queue.h"

#include <stdio.h>
#include <string.h>

static void copy_plane(uint8_t *dst, const negobs_image_u8_t *img)
{
    int32_t y;
    for (y = 0; y < img->height; y++) {
        memcpy(dst + (size_t)y * (size_t)img->width,
               negobs_image_u8_row(img, y), (size_t)img->width);
    }
}

/* Open (first pair) and write the slot; the caller holds no lock. */
static negobs_status_t write_slot(negobs_record_queue_t *q, uint32_t slot)
{
    const negobs_recq_slot_t *m = &q->meta[slot];
    uint8_t *px = q->buf + (size_t)slot * q->slot_bytes;
    size_t frame = (size_t)m->width * (size_t)m->height;
    negobs_frame_pair_t p;
    negobs_status_t s;
    if (!q->rec.is_open) {
        s = negobs_recorder_open(&q->rec, q->dir, m->width, m->height);
        if (s != NEGOBS_OK) {
            return s;
        }
        if (q->write_fn != NULL) {
            q->rec.write_fn = q->write_fn;
        }
    }
    memset(&p, 0, sizeof p);
    p.left.y.data = px;
    p.right.y.data = px + frame;
    p.left.y.width = p.right.y.width = m->width;
    p.left.y.height = p.right.y.height = m->height;
    p.left.y.stride = p.right.y.stride = m->width;
    p.left.ts_ns = m->ts_left_ns;
    p.right.ts_ns = m->ts_right_ns;
    p.left.sequence = p.right.sequence = m->sequence;
    return negobs_recorder_write(&q->rec, &p);
}

static void *writer(void *arg)
{
    negobs_record_queue_t *q = arg;
    (void)pthread_mutex_lock(&q->lock);
    for (;;) {
        uint32_t slot;
        negobs_status_t s;
        while (q->count == 0 && !q->stop) {
            (void)pthread_cond_wait(&q->cond, &q->lock);
        }
        if (q->count == 0) {
            break; /* stop requested and everything written */
        }
        slot = q->head;
        q->busy = true;
        (void)pthread_mutex_unlock(&q->lock);
        s = write_slot(q, slot);
        (void)pthread_mutex_lock(&q->lock);
        q->busy = false;
        q->head = (q->head + 1u) % q->n_slots;
        q->count--;
        if (s == NEGOBS_OK) {
            q->written++;
            q->state = NEGOBS_RECQ_RECORDING;
            continue;
        }
        (void)snprintf(q->errmsg, sizeof q->errmsg, "%s", q->rec.errmsg);
        q->state = NEGOBS_RECQ_FAILED;
        q->discarded = q->count;
        q->count = 0;
        break;
    }
    (void)pthread_mutex_unlock(&q->lock);
    negobs_recorder_close(&q->rec);
    return NULL;
}

negobs_status_t negobs_recq_start(negobs_record_queue_t *q, const char *dir,
                                  uint8_t *buf, size_t slot_bytes,
                                  uint32_t n_slots)
{
    ssize_t (*hook)(int, const void *, size_t);
    if (q == NULL || dir == NULL || buf == NULL || slot_bytes < 2u ||
        n_slots < 1u || n_slots > NEGOBS_RECQ_SLOTS_MAX ||
        strlen(dir) >= sizeof q->dir) {
        return NEGOBS_ERR_INVAL;
    }
    hook = q->write_fn;
    memset(q, 0, sizeof *q);
    q->write_fn = hook;
    memcpy(q->dir, dir, strlen(dir) + 1u);
    q->buf = buf;
    q->slot_bytes = slot_bytes;
    q->n_slots = n_slots;
    q->state = NEGOBS_RECQ_WAITING;
    if (pthread_mutex_init(&q->lock, NULL) != 0) {
        return NEGOBS_ERR_IO;
    }
    if (pthread_cond_init(&q->cond, NULL) != 0) {
        (void)pthread_mutex_destroy(&q->lock);
        return NEGOBS_ERR_IO;
    }
    if (pthread_create(&q->thread, NULL, writer, q) != 0) {
        (void)pthread_cond_destroy(&q->cond);
        (void)pthread_mutex_destroy(&q->lock);
        q->state = NEGOBS_RECQ_FAILED;
        (void)snprintf(q->errmsg, sizeof q->errmsg,
                       "cannot start the writer thread");
        return NEGOBS_ERR_IO;
    }
    q->running = true;
    return NEGOBS_OK;
}

int negobs_recq_push(negobs_record_queue_t *q, const negobs_frame_pair_t *pair)
{
    uint32_t slot;
    size_t frame;
    negobs_recq_slot_t *m;
    if (q == NULL || pair == NULL || !q->running) {
        return -1;
    }
    (void)pthread_mutex_lock(&q->lock);
    if (q->state == NEGOBS_RECQ_FAILED || q->stop) {
        (void)pthread_mutex_unlock(&q->lock);
        return -1;
    }
    frame = (size_t)pair->left.y.width * (size_t)pair->left.y.height;
    if (pair->left.y.width < 1 || pair->left.y.height < 1 ||
        pair->right.y.width != pair->left.y.width ||
        pair->right.y.height != pair->left.y.height ||
        2u * frame > q->slot_bytes) {
        q->dropped++;
        (void)pthread_mutex_unlock(&q->lock);
        return -2;
    }
    if (q->count == q->n_slots) {
        q->dropped++; /* drop newest: see the header */
        (void)pthread_mutex_unlock(&q->lock);
        return 0;
    }
    slot = (q->head + q->count) % q->n_slots;
    (void)pthread_mutex_unlock(&q->lock);
    /* The slot is free: the writer only touches queued slots, and only
     * this thread queues. Copy without the lock. */
    m = &q->meta[slot];
    copy_plane(q->buf + (size_t)slot * q->slot_bytes, &pair->left.y);
    copy_plane(q->buf + (size_t)slot * q->slot_bytes + frame, &pair->right.y);
    m->width = pair->left.y.width;
    m->height = pair->left.y.height;
    m->ts_left_ns = pair->left.ts_ns;
    m->ts_right_ns = pair->right.ts_ns;
    m->sequence = pair->left.sequence;
    (void)pthread_mutex_lock(&q->lock);
    if (q->state == NEGOBS_RECQ_FAILED) {
        (void)pthread_mutex_unlock(&q->lock);
        return -1;
    }
    q->count++;
    (void)pthread_cond_signal(&q->cond);
    (void)pthread_mutex_unlock(&q->lock);
    return 1;
}

void negobs_recq_stats(negobs_record_queue_t *q, negobs_recq_stats_t *out)
{
    memset(out, 0, sizeof *out);
    if (q == NULL || !q->running) {
        out->state = q != NULL ? q->state : NEGOBS_RECQ_OFF;
        if (q != NULL) {
            out->written = q->written;
            out->dropped = q->dropped;
            out->discarded = q->discarded;
            (void)snprintf(out->errmsg, sizeof out->errmsg, "%s", q->errmsg);
        }
        return;
    }
    (void)pthread_mutex_lock(&q->lock);
    out->state = q->state;
    out->written = q->written;
    out->dropped = q->dropped;
    out->discarded = q->discarded;
    (void)snprintf(out->errmsg, sizeof out->errmsg, "%s", q->errmsg);
    (void)pthread_mutex_unlock(&q->lock);
}

void negobs_recq_stop(negobs_record_queue_t *q)
{
    if (q == NULL || !q->running) {
        return;
    }
    (void)pthread_mutex_lock(&q->lock);
    q->stop = true;
    (void)pthread_cond_signal(&q->cond);
    (void)pthread_mutex_unlock(&q->lock);
    (void)pthread_join(q->thread, NULL);
    q->running = false;
    (void)pthread_cond_destroy(&q->cond);
    (void)pthread_mutex_destroy(&q->lock);
}

const char *negobs_recq_state_name(negobs_recq_state_t s)
{
    switch (s) {
    case NEGOBS_RECQ_OFF: return "off";
    case NEGOBS_RECQ_WAITING: return "waiting";
    case NEGOBS_RECQ_RECORDING: return "recording";
    case NEGOBS_RECQ_FAILED: return "failed";
    default: return "?";
    }
}

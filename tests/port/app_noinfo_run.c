/*
 * End-to-end no-information latency of the real negobs_run on the host.
 *
 *   app_noinfo_run NEGOBS_RUN CONF FRAMES_DIR W H K STALLS [TOL_MS]
 *                  [BATCH] [PACE_MS]
 *
 * FRAMES_DIR holds left.y / right.y: K raw W x H frames each (a flat walk
 * that negobs_run judges "clear"). The harness writes a recorded session
 * whose left.y is a FIFO and feeds it in batches of BATCH pairs (10), one
 * pair every PACE_MS (0: as fast as they are read); between batches it
 * stops writing for STALL_MS, so negobs_run's main loop blocks in the
 * replay read, as with a camera driver that hangs. Paced at the frame
 * rate of a walk whose K frames are one continuous walk (K at least
 * BATCH x (STALLS + 1)), the detector measures the walk after a stall as
 * on a camera: the floor the wearer may have reached during the stall
 * is vouched again once walked over (docs/DETECTION.md 10.2). Every line negobs_run
 * prints (stdout: `--alert console` motor changes; stderr: logs with
 * `--log-level debug`, one "pair N verdict V" per pair) is stamped on
 * arrival with CLOCK_MONOTONIC. Latency = first motor-on line after the
 * last pair of a batch - that pair's line. A stall counts only when the
 * motor was off and the pattern "off" at that pair (a clear verdict, no
 * pulse running); the watchdog is watchdog_ms in CONF.
 * Exit 0 when every counted stall gives watchdog_ms +- TOL_MS (the
 * stamps are taken here, on arrival, so scheduling jitter of this
 * harness counts both ways; test_app_noinfo.c measures in-process) and at least half of the stalls count (77, skipped, when fewer
 * count: pairs slower than watchdog_ms leave nothing to measure); prints
 * every latency.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define BATCH 10
#define STALL_MS 1300
#define MAX_STALLS 32

static uint64_t now_us(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* Line assembly per stream. */
typedef struct stream {
    int fd;
    char buf[4096];
    size_t len;
} stream_t;

/* What the harness follows in negobs_run's output. */
typedef struct watch {
    long last_pair;        /* index of the last "pair N" line        */
    uint64_t last_pair_us; /* its arrival                             */
    int motor_on;          /* last console level                      */
    int pattern_off;       /* last "pattern X -> off"                 */
    long want_pair;        /* pair that ends the current batch        */
    uint64_t t_want_us;    /* arrival of that pair's line (0: not yet) */
    int want_valid;        /* motor off and pattern off at that pair  */
    uint64_t first_on_us;  /* first motor-on line after it            */
    FILE *log;
} watch_t;

static void on_line(watch_t *w, const char *line, int is_stdout, uint64_t t)
{
    long n;
    const char *p;
    fprintf(w->log, "%llu %s %s\n", (unsigned long long)t,
            is_stdout ? "out" : "err", line);
    if (is_stdout && strncmp(line, "motor ", 6) == 0) {
        int on = strstr(line, ": ON ") != NULL;
        if (on && w->t_want_us != 0 && w->first_on_us == 0) {
            w->first_on_us = t;
        }
        w->motor_on = on;
        return;
    }
    p = strstr(line, "pattern ");
    if (p != NULL && strstr(p, " -> ") != NULL) {
        w->pattern_off = strstr(p, " -> off") != NULL;
        return;
    }
    p = strstr(line, "debug: pair ");
    if (p != NULL && sscanf(p + 12, "%ld", &n) == 1) {
        w->last_pair = n;
        w->last_pair_us = t;
        if (n == w->want_pair) {
            w->t_want_us = t;
            w->want_valid = !w->motor_on && w->pattern_off &&
                            strstr(p, "verdict clear") != NULL;
        }
    }
}

static int pump(stream_t *s, watch_t *w, int is_stdout)
{
    ssize_t r = read(s->fd, s->buf + s->len, sizeof s->buf - 1 - s->len);
    uint64_t t = now_us();
    char *nl;
    if (r <= 0) {
        return -1;
    }
    s->len += (size_t)r;
    s->buf[s->len] = '\0';
    while ((nl = strchr(s->buf, '\n')) != NULL) {
        *nl = '\0';
        on_line(w, s->buf, is_stdout, t);
        s->len -= (size_t)(nl + 1 - s->buf);
        memmove(s->buf, nl + 1, s->len + 1);
    }
    if (s->len == sizeof s->buf - 1) {
        s->len = 0; /* overlong line: drop */
    }
    return 0;
}

/* Read both streams for up to ms milliseconds (or until EOF of both). */
static int drain(stream_t *st, watch_t *w, int ms)
{
    uint64_t end = now_us() + (uint64_t)ms * 1000u;
    for (;;) {
        struct pollfd pf[2];
        int n = 0;
        int i;
        uint64_t t = now_us();
        if (t >= end) {
            return 0;
        }
        for (i = 0; i < 2; i++) {
            pf[i].fd = st[i].fd;
            pf[i].events = POLLIN;
            pf[i].revents = 0;
            n += st[i].fd >= 0;
        }
        if (n == 0) {
            return -1;
        }
        if (poll(pf, 2, (int)((end - t) / 1000u) + 1) < 0 && errno != EINTR) {
            return -1;
        }
        for (i = 0; i < 2; i++) {
            if (st[i].fd >= 0 && (pf[i].revents & (POLLIN | POLLHUP))) {
                if (pump(&st[i], w, i == 0) != 0) {
                    (void)close(st[i].fd);
                    st[i].fd = -1;
                }
            }
        }
    }
}

static int write_all(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t r = write(fd, p, n);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r <= 0) {
            return -1;
        }
        p += r;
        n -= (size_t)r;
    }
    return 0;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a;
    uint64_t y = *(const uint64_t *)b;
    return x < y ? -1 : x > y ? 1 : 0;
}

int main(int argc, char **argv)
{
    char dir[] = "/tmp/negobs-noinfo-XXXXXX";
    char path[512];
    char arg[600];
    unsigned char *frames_l;
    unsigned char *frames_r;
    size_t fsz;
    long w, h, k, stalls, tol_ms = 50, wdog_ms = 300;
    long batch = BATCH;
    long pace_ms = 0;
    long total;
    long i;
    int po[2];
    int pe[2];
    int fifo;
    pid_t pid;
    int status = 0;
    stream_t st[2];
    watch_t wt;
    uint64_t lat[MAX_STALLS];
    int n_lat = 0;
    int bad = 0;
    FILE *f;
    char line[256];

    if (argc < 8) {
        fprintf(stderr,
                "usage: %s NEGOBS_RUN CONF FRAMES_DIR W H K STALLS "
                "[TOL_MS] [BATCH] [PACE_MS]\n",
                argv[0]);
        return 2;
    }
    w = atol(argv[4]);
    h = atol(argv[5]);
    k = atol(argv[6]);
    stalls = atol(argv[7]);
    if (argc > 8) {
        tol_ms = atol(argv[8]);
    }
    if (argc > 9) {
        batch = atol(argv[9]);
    }
    if (argc > 10) {
        pace_ms = atol(argv[10]);
    }
    if (w < 16 || h < 16 || w * h > 4000000 || k < 1 || stalls < 1 ||
        stalls > MAX_STALLS || batch < 1 || batch > 1000 || pace_ms < 0 ||
        pace_ms > 1000) {
        fprintf(stderr, "app_noinfo_run: bad arguments\n");
        return 2;
    }
    f = fopen(argv[2], "r");
    while (f != NULL && fgets(line, sizeof line, f) != NULL) {
        (void)sscanf(line, " watchdog_ms = %ld", &wdog_ms);
    }
    if (f != NULL) {
        (void)fclose(f);
    }
    fsz = (size_t)(w * h);
    frames_l = malloc(fsz * (size_t)k);
    frames_r = malloc(fsz * (size_t)k);
    (void)snprintf(path, sizeof path, "%s/left.y", argv[3]);
    f = fopen(path, "rb");
    if (frames_l == NULL || frames_r == NULL || f == NULL ||
        fread(frames_l, fsz, (size_t)k, f) != (size_t)k) {
        fprintf(stderr, "app_noinfo_run: cannot read %s\n", path);
        return 1;
    }
    (void)fclose(f);
    (void)snprintf(path, sizeof path, "%s/right.y", argv[3]);
    f = fopen(path, "rb");
    if (f == NULL || fread(frames_r, fsz, (size_t)k, f) != (size_t)k) {
        fprintf(stderr, "app_noinfo_run: cannot read %s\n", path);
        return 1;
    }
    (void)fclose(f);

    /* The session: frames.txt and right.y complete, left.y a FIFO. */
    if (mkdtemp(dir) == NULL) {
        perror("mkdtemp");
        return 1;
    }
    total = batch * (stalls + 1);
    (void)snprintf(path, sizeof path, "%s/session.txt", dir);
    f = fopen(path, "w");
    fprintf(f, "negobs-session 1\nwidth %ld\nheight %ld\n", w, h);
    (void)fclose(f);
    (void)snprintf(path, sizeof path, "%s/frames.txt", dir);
    f = fopen(path, "w");
    fprintf(f, "# index left_ns right_ns sequence\n");
    for (i = 0; i < total; i++) {
        fprintf(f, "%ld %ld %ld %ld\n", i, i * 100000000L, i * 100000000L, i);
    }
    (void)fclose(f);
    (void)snprintf(path, sizeof path, "%s/right.y", dir);
    f = fopen(path, "wb");
    for (i = 0; i < total; i++) {
        (void)fwrite(frames_r + fsz * (size_t)(i % k), 1, fsz, f);
    }
    (void)fclose(f);
    (void)snprintf(path, sizeof path, "%s/left.y", dir);
    if (mkfifo(path, 0600) != 0) {
        perror("mkfifo");
        return 1;
    }

    if (pipe(po) != 0 || pipe(pe) != 0) {
        perror("pipe");
        return 1;
    }
    (void)snprintf(arg, sizeof arg, "replay:%s", dir);
    pid = fork();
    if (pid == 0) {
        (void)dup2(po[1], 1);
        (void)dup2(pe[1], 2);
        (void)close(po[0]);
        (void)close(pe[0]);
        execl(argv[1], argv[1], "--config", argv[2], "--fps", "0", "--alert",
              "console", "--log-level", "debug", arg, (char *)NULL);
        _exit(127);
    }
    (void)close(po[1]);
    (void)close(pe[1]);
    st[0].fd = po[0];
    st[0].len = 0;
    st[1].fd = pe[0];
    st[1].len = 0;
    memset(&wt, 0, sizeof wt);
    wt.last_pair = -1;
    wt.want_pair = -1;
    (void)snprintf(path, sizeof path, "%s/lines.txt", dir);
    wt.log = fopen(path, "w");
    (void)snprintf(path, sizeof path, "%s/left.y", dir);
    /* Blocks until negobs_run opens the replay (after READY). */
    fifo = open(path, O_WRONLY);
    if (fifo < 0) {
        perror("open fifo");
        kill(pid, SIGTERM);
        return 1;
    }
    for (i = 0; i <= stalls; i++) {
        long j;
        /* set before the batch: a paced batch's last line may arrive
         * while it is still being written */
        wt.want_pair = (i + 1) * batch - 1;
        wt.t_want_us = 0;
        wt.first_on_us = 0;
        for (j = 0; j < batch; j++) {
            long idx = i * batch + j;
            if (write_all(fifo, frames_l + fsz * (size_t)(idx % k), fsz) !=
                0) {
                fprintf(stderr, "app_noinfo_run: FIFO write failed\n");
                kill(pid, SIGTERM);
                return 1;
            }
            (void)drain(st, &wt, (int)pace_ms);
        }
        if (i == stalls) {
            break;
        }
        /* stall: nothing more until STALL_MS after the batch's last
         * pair was judged */
        while (wt.t_want_us == 0 && drain(st, &wt, 100) == 0) {
        }
        (void)drain(st, &wt, STALL_MS);
        if (wt.t_want_us != 0 && wt.want_valid && wt.first_on_us != 0) {
            lat[(size_t)n_lat] = wt.first_on_us - wt.t_want_us;
            n_lat++;
            printf(
                "stall %ld: pair %ld clear at +0, motor on at +%llu.%03llu ms\n",
                i, wt.want_pair,
                (unsigned long long)(lat[(size_t)n_lat - 1u] / 1000u),
                (unsigned long long)(lat[(size_t)n_lat - 1u] % 1000u));
        } else {
            printf("stall %ld: not counted (%s)\n", i,
                   wt.t_want_us == 0 ? "pair line missing"
                   : !wt.want_valid  ? "motor or pattern not off at the "
                                       "last pair"
                                     : "no motor-on line");
            if (wt.t_want_us != 0 && wt.want_valid) {
                bad++; /* clear, silent, and then nothing: a failure */
            }
        }
    }
    (void)close(fifo);
    while (drain(st, &wt, 1000) == 0) {
    }
    (void)waitpid(pid, &status, 0);
    if (wt.log != NULL) {
        (void)fclose(wt.log);
    }
    printf("negobs_run exit status %d\n",
           WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    if (n_lat > 0) {
        qsort(lat, (size_t)n_lat, sizeof lat[0], cmp_u64);
        printf("no-info latency, %d of %ld stalls (watchdog_ms %ld): min "
               "%llu.%03llu median %llu.%03llu max %llu.%03llu ms\n",
               n_lat, stalls, wdog_ms, (unsigned long long)(lat[0] / 1000u),
               (unsigned long long)(lat[0] % 1000u),
               (unsigned long long)(lat[(size_t)n_lat / 2u] / 1000u),
               (unsigned long long)(lat[(size_t)n_lat / 2u] % 1000u),
               (unsigned long long)(lat[(size_t)n_lat - 1u] / 1000u),
               (unsigned long long)(lat[(size_t)n_lat - 1u] % 1000u));
    }
    for (i = 0; i < n_lat; i++) {
        /* Both ends are stamped on arrival here, so the harness's own
         * scheduling shows in both directions: +-TOL_MS. */
        if (lat[(size_t)i] + (uint64_t)tol_ms * 1000u <
                (uint64_t)wdog_ms * 1000u ||
            lat[(size_t)i] > (uint64_t)(wdog_ms + tol_ms) * 1000u) {
            bad++;
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        printf("FAIL: negobs_run did not end cleanly\n");
        bad++;
    }
    if (bad == 0 && n_lat * 2 < stalls) {
        /* Pairs slower than watchdog_ms (a loaded host) make the motor
         * play no-information between pairs: nothing to measure. Say so
         * rather than pass or fail. */
        printf("SKIP: only %d of %ld stalls measurable (pairs too slow "
               "on this host?)\n",
               n_lat, stalls);
        return 77;
    }
    if (bad) {
        printf("FAIL (every line, stamped: %s/lines.txt)\n", dir);
    } else {
        static const char *const names[] = {"session.txt", "frames.txt",
                                            "right.y", "left.y", "lines.txt"};
        for (i = 0; i < 5; i++) {
            (void)snprintf(path, sizeof path, "%s/%s", dir, names[i]);
            (void)unlink(path);
        }
        (void)rmdir(dir);
        printf("PASS\n");
    }
    free(frames_l);
    free(frames_r);
    return bad ? 1 : 0;
}

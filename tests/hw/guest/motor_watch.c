/*
 * motor_watch: outside observer of the motor line for the negobs_run
 * sections of the emulated-hardware tests (tests/hw).
 *
 *   motor_watch [-i ms] FILE
 *       Reads FILE (gpio-sim's sim_gpioN/value, or a PWM channel's
 *       duty_cycle: anything > 0 counts as on) every -i ms (default 5) and
 *       prints one line per change of state, "T V" with T = CLOCK_BOOTTIME
 *       in seconds (same clock as /proc/uptime) and V = 0 or 1; the first
 *       line is the state at start.  Runs until SIGTERM/SIGINT.
 *   motor_watch [-i ms] -c DIR
 *       The same for the first line of a gpio-sim chip configured in
 *       configfs DIR: the value file is found from DIR/dev_name and
 *       DIR/bank0/chip_name, and found again whenever it cannot be read.
 *       So the observer can run before the chip comes (back) under a
 *       number nobody knows yet: a watcher started after the chip
 *       returned misses what the line did meanwhile.
 *   motor_watch now
 *       Prints the current CLOCK_BOOTTIME (mark an event in the same clock).
 *   motor_watch press FILE MS
 *       A button press on a gpio-sim line: writes "pull-down" to FILE (its
 *       sim_gpioN/pull), sleeps MS ms, writes "pull-up", and prints the
 *       boot times of both writes.  One process holds the press, so a
 *       loaded TCG guest stretches it by one wake-up, not by the shell's
 *       process starts (a 400 ms press held from a script read 1.2 s).
 *
 * Every sample also reports the largest gap between two samples at exit
 * ("# samples N max_gap_ms G") so the run shows how finely the line was
 * observed under TCG.  C99 + POSIX, static aarch64.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#ifndef CLOCK_BOOTTIME
#define CLOCK_BOOTTIME 7
#endif

static volatile sig_atomic_t stop;
static void on_sig(int s)
{
	(void)s;
	stop = 1;
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_BOOTTIME, &ts);
	return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

static int read_state(const char *path)
{
	char buf[32];
	ssize_t n;
	int fd = open(path, O_RDONLY);
	if (fd < 0)
		return -1;
	n = read(fd, buf, sizeof buf - 1);
	close(fd);
	if (n <= 0)
		return -1;
	buf[n] = '\0';
	return strtol(buf, NULL, 10) > 0;
}

/* Reads the first line of DIR/NAME into buf, without the newline. */
static int read_line(const char *dir, const char *name, char *buf, size_t n)
{
	char p[512];
	FILE *f;
	size_t len;
	snprintf(p, sizeof p, "%s/%s", dir, name);
	f = fopen(p, "r");
	if (!f)
		return -1;
	if (!fgets(buf, (int)n, f)) {
		fclose(f);
		return -1;
	}
	fclose(f);
	len = strcspn(buf, "\n");
	buf[len] = '\0';
	return len > 0 ? 0 : -1;
}

/* The sim value file of line 0 of the gpio-sim chip configured in DIR. */
static int resolve_sim(const char *dir, char *path, size_t n)
{
	char dev[128], chip[128];
	if (read_line(dir, "dev_name", dev, sizeof dev) != 0 ||
	    read_line(dir, "bank0/chip_name", chip, sizeof chip) != 0)
		return -1;
	snprintf(path, n, "/sys/devices/platform/%s/%s/sim_gpio0/value", dev,
		 chip);
	return 0;
}

static int write_str(const char *path, const char *s)
{
	int fd = open(path, O_WRONLY);
	ssize_t n;
	if (fd < 0)
		return -1;
	n = write(fd, s, strlen(s));
	close(fd);
	return n == (ssize_t)strlen(s) ? 0 : -1;
}

static int press(const char *path, int ms)
{
	struct timespec d;
	double t0, t1;
	if (ms <= 0 || write_str(path, "pull-down") != 0) {
		fprintf(stderr, "motor_watch: cannot press %s\n", path);
		return 1;
	}
	t0 = now_s();
	d.tv_sec = ms / 1000;
	d.tv_nsec = (long)(ms % 1000) * 1000000L;
	while (nanosleep(&d, &d) != 0 && errno == EINTR)
		;
	if (write_str(path, "pull-up") != 0) {
		fprintf(stderr, "motor_watch: cannot release %s\n", path);
		return 1;
	}
	t1 = now_s();
	printf("%.3f %.3f\n", t0, t1);
	return 0;
}

int main(int argc, char **argv)
{
	int ms = 5, last = -2, v;
	const char *path, *simdir = NULL;
	static char simpath[512];
	unsigned long samples = 0;
	double prev = 0, gap = 0, t;
	struct sigaction sa;
	struct timespec d;

	if (argc == 2 && strcmp(argv[1], "now") == 0) {
		printf("%.3f\n", now_s());
		return 0;
	}
	if (argc == 4 && strcmp(argv[1], "press") == 0)
		return press(argv[2], atoi(argv[3]));
	if (argc == 4 && strcmp(argv[1], "-i") == 0) {
		ms = atoi(argv[2]);
		path = argv[3];
	} else if (argc == 2) {
		path = argv[1];
	} else if (argc == 5 && strcmp(argv[1], "-i") == 0 &&
		   strcmp(argv[3], "-c") == 0) {
		ms = atoi(argv[2]);
		simdir = argv[4];
		path = simpath;
	} else {
		fprintf(stderr,
			"usage: motor_watch [-i ms] FILE | "
			"motor_watch [-i ms] -c DIR | motor_watch now | "
			"motor_watch press FILE MS\n");
		return 2;
	}
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_sig;
	sigaction(SIGTERM, &sa, NULL);
	sigaction(SIGINT, &sa, NULL);
	setvbuf(stdout, NULL, _IOLBF, 0);
	d.tv_sec = ms / 1000;
	d.tv_nsec = (long)(ms % 1000) * 1000000L;
	while (!stop) {
		v = read_state(path);
		if (v < 0 && simdir &&
		    resolve_sim(simdir, simpath, sizeof simpath) == 0)
			v = read_state(path);
		t = now_s();
		if (samples > 0 && t - prev > gap)
			gap = t - prev;
		prev = t;
		samples++;
		if (v >= 0 && v != last) {
			printf("%.3f %d\n", t, v);
			last = v;
		}
		nanosleep(&d, NULL);
	}
	printf("# samples %lu max_gap_ms %.0f\n", samples, gap * 1000.0);
	return 0;
}

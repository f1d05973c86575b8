/*
 * pwm_test: drive one PWM channel through the sysfs ABI
 * (/sys/class/pwm/pwmchipN/{export,unexport}, pwmM/{period,duty_cycle,
 * enable}) and read the state back, for the emulated-hardware tests.
 *
 *   pwm_test [-r CLASSDIR] [-d DEVNAME] [-n CHANNEL] [-D DEBUGFS]
 *
 *   -r  sysfs class root (default /sys/class/pwm); a plain directory laid
 *       out like it works too (host-side dry run, no kernel rules checked)
 *   -d  device name the chip belongs to (default "pwm-sim"); the chip is
 *       the pwmchipN whose "device" link ends in that name, or pwmchip0
 *       when no chip has a device link (fake tree)
 *   -n  channel (default 0)
 *   -D  /sys/kernel/debug/pwm to cross-check against ("" to skip)
 *
 * Steps: export (waits up to 1 s for pwmM/), period 1 ms, duty 25 %,
 * enable, read back; duty_cycle > period must fail with EINVAL (kernel
 * only); duty 75 %; debugfs must show the same state; disable; unexport.
 * Exit 0 when every check passed.
 */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static int fails;
static int fake; /* no device links: plain files, skip kernel-only checks */

#define CHECK(cond, ...)                                                       \
	do {                                                                   \
		if (cond) {                                                    \
			printf("  ok   ");                                     \
		} else {                                                       \
			printf("  FAIL ");                                     \
			fails++;                                               \
		}                                                              \
		printf(__VA_ARGS__);                                           \
		putchar('\n');                                                 \
	} while (0)

/* writes `val` to dir/name with one write(); returns 0 or errno.  Opened
 * write-only: sysfs refuses read access to write-only attributes (export). */
static int put(const char *dir, const char *name, const char *val)
{
	char p[512];
	int fd, e = 0;
	size_t n = strlen(val);
	snprintf(p, sizeof p, "%s/%s", dir, name);
	fd = open(p, fake ? O_WRONLY | O_CREAT | O_TRUNC : O_WRONLY, 0644);
	if (fd < 0)
		return errno;
	if (write(fd, val, n) != (ssize_t)n)
		e = errno ? errno : EIO;
	if (close(fd) != 0 && !e)
		e = errno;
	return e;
}

static long long get(const char *dir, const char *name)
{
	char p[512];
	long long v = -1;
	FILE *f;
	snprintf(p, sizeof p, "%s/%s", dir, name);
	f = fopen(p, "r");
	if (!f)
		return -1;
	if (fscanf(f, "%lld", &v) != 1)
		v = -1;
	fclose(f);
	return v;
}

static int is_dir(const char *p)
{
	struct stat st;
	return stat(p, &st) == 0 && S_ISDIR(st.st_mode);
}

/* Finds the debugfs line of channel `ch` of the chip whose header names
 * device `dev` ("platform/pwm-sim, 2 PWM devices"), copies it to out. */
static int debugfs_line(const char *file, const char *dev, int ch, char *out,
			size_t n)
{
	FILE *f = fopen(file, "r");
	char line[512], tag[32], hdr[300];
	int in = 0, found = 0;
	if (!f)
		return -1;
	snprintf(tag, sizeof tag, " pwm-%-3d", ch);
	snprintf(hdr, sizeof hdr, "/%s,", dev);
	while (fgets(line, sizeof line, f)) {
		if (line[0] != ' ' && line[0] != '\n')
			in = strstr(line, hdr) != NULL;
		else if (in && strncmp(line, tag, strlen(tag)) == 0) {
			char *nl = strchr(line, '\n');
			if (nl)
				*nl = 0;
			snprintf(out, n, "%s", line);
			found = 1;
			break;
		}
	}
	fclose(f);
	return found ? 0 : -1;
}

int main(int argc, char **argv)
{
	const char *root = "/sys/class/pwm", *dev = "pwm-sim";
	const char *dbg = "/sys/kernel/debug/pwm";
	char chip[300] = "", pwm[320], buf[64], line[512];
	int ch = 0, opt, e, i;
	DIR *d;
	struct dirent *de;

	while ((opt = getopt(argc, argv, "r:d:n:D:")) != -1) {
		switch (opt) {
		case 'r':
			root = optarg;
			break;
		case 'd':
			dev = optarg;
			break;
		case 'n':
			ch = atoi(optarg);
			break;
		case 'D':
			dbg = optarg;
			break;
		default:
			fprintf(stderr, "usage: pwm_test [-r CLASSDIR] "
					"[-d DEVNAME] [-n CH] [-D DEBUGFS]\n");
			return 2;
		}
	}
	setvbuf(stdout, NULL, _IOLBF, 0);

	d = opendir(root);
	if (!d) {
		printf("pwm_test: FAIL cannot open %s: %s\n", root,
		       strerror(errno));
		return 1;
	}
	fake = 1;
	while ((de = readdir(d)) != NULL) {
		char l[300], tgt[512];
		ssize_t k;
		const char *base;
		if (strncmp(de->d_name, "pwmchip", 7) != 0)
			continue;
		snprintf(l, sizeof l, "%s/%s/device", root, de->d_name);
		k = readlink(l, tgt, sizeof tgt - 1);
		if (k < 0) {
			if (!chip[0])
				snprintf(chip, sizeof chip, "%s/%s", root,
					 de->d_name);
			continue;
		}
		tgt[k] = 0;
		base = strrchr(tgt, '/');
		base = base ? base + 1 : tgt;
		if (strcmp(base, dev) == 0) {
			snprintf(chip, sizeof chip, "%s/%s", root, de->d_name);
			fake = 0;
			break;
		}
	}
	closedir(d);
	if (!chip[0] || (!fake && !is_dir(chip))) {
		printf("pwm_test: FAIL no pwmchip of device '%s' in %s\n", dev,
		       root);
		return 1;
	}
	if (fake)
		dbg = "";
	printf("pwm_test: chip %s (npwm %lld), channel %d%s\n", chip,
	       get(chip, "npwm"), ch, fake ? " [plain-file tree]" : "");
	CHECK(get(chip, "npwm") > ch, "channel %d < npwm", ch);

	snprintf(pwm, sizeof pwm, "%s/pwm%d", chip, ch);
	snprintf(buf, sizeof buf, "%d", ch);
	e = put(chip, "export", buf);
	CHECK(e == 0 || e == EBUSY, "export %d (%s)", ch,
	      e ? strerror(e) : "ok");
	for (i = 0; i < 100 && !is_dir(pwm); i++) {
		struct timespec ts = {0, 10 * 1000 * 1000};
		nanosleep(&ts, NULL);
	}
	CHECK(is_dir(pwm), "%s appeared", pwm);

	CHECK(put(pwm, "period", "1000000") == 0 &&
		  get(pwm, "period") == 1000000,
	      "period 1000000 ns reads %lld", get(pwm, "period"));
	CHECK(put(pwm, "duty_cycle", "250000") == 0 &&
		  get(pwm, "duty_cycle") == 250000,
	      "duty_cycle 250000 ns reads %lld", get(pwm, "duty_cycle"));
	CHECK(put(pwm, "enable", "1") == 0 && get(pwm, "enable") == 1,
	      "enable 1 reads %lld", get(pwm, "enable"));
	if (!fake) {
		e = put(pwm, "duty_cycle", "2000000");
		CHECK(e == EINVAL && get(pwm, "duty_cycle") == 250000,
		      "duty_cycle > period refused (%s), still %lld",
		      e ? strerror(e) : "accepted", get(pwm, "duty_cycle"));
	}
	CHECK(put(pwm, "duty_cycle", "750000") == 0 &&
		  get(pwm, "duty_cycle") == 750000,
	      "duty_cycle 750000 ns reads %lld", get(pwm, "duty_cycle"));
	if (dbg[0]) {
		int ok = debugfs_line(dbg, dev, ch, line, sizeof line) == 0;
		CHECK(ok && strstr(line, " requested") &&
			  strstr(line, " enabled") &&
			  strstr(line, " period: 1000000 ns") &&
			  strstr(line, " duty: 750000 ns") &&
			  strstr(line, " polarity: normal"),
		      "debugfs: %s", ok ? line : "(no line)");
	}
	CHECK(put(pwm, "enable", "0") == 0 && get(pwm, "enable") == 0,
	      "enable 0 reads %lld", get(pwm, "enable"));
	if (dbg[0]) {
		int ok = debugfs_line(dbg, dev, ch, line, sizeof line) == 0;
		CHECK(ok && !strstr(line, " enabled"), "debugfs: %s",
		      ok ? line : "(no line)");
	}
	e = put(chip, "unexport", buf);
	CHECK(e == 0, "unexport %d (%s)", ch, e ? strerror(e) : "ok");
	if (!fake) {
		for (i = 0; i < 100 && is_dir(pwm); i++) {
			struct timespec ts = {0, 10 * 1000 * 1000};
			nanosleep(&ts, NULL);
		}
		CHECK(!is_dir(pwm), "%s removed", pwm);
	}
	printf("pwm_test: %s\n", fails ? "FAIL" : "OK");
	return fails ? 1 : 0;
}

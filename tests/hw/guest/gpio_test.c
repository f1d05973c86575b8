/*
 * gpio_test: drive one GPIO line through the character device (uAPI v2)
 * and read it back both through the chardev and through an outside observer
 * in the kernel, for the emulated-hardware tests (tests/hw).
 *
 *   gpio_test -l LABEL -o OFFSET [-s SIMVALUE] [-c CONSUMER]
 *
 *   -l LABEL   chip label to find among /dev/gpiochip* (e.g. "9030000.pl061"
 *              for QEMU virt's PL061, or a gpio-sim chip's label)
 *   -o OFFSET  line offset to drive as output
 *   -s FILE    gpio-sim's sysfs value file of that line (sim_gpioN/value);
 *              without it the observer is /sys/kernel/debug/gpio (gpiolib's
 *              own view, which reads the controller's data register)
 *
 * It requests the line as output with consumer "negobs-motor" (checks that
 * LINEINFO shows it used by that consumer), drives 1,0,1,0 and after each
 * write checks GET_VALUES and the observer.  Exit 0 when all matched.
 */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

static int fails;

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

static int open_chip(const char *label, char *path, size_t n,
		     struct gpiochip_info *info)
{
	DIR *d = opendir("/dev");
	struct dirent *de;
	int fd = -1;
	if (!d)
		return -1;
	while ((de = readdir(d)) != NULL) {
		if (strncmp(de->d_name, "gpiochip", 8) != 0)
			continue;
		snprintf(path, n, "/dev/%s", de->d_name);
		fd = open(path, O_RDWR | O_CLOEXEC);
		if (fd < 0)
			continue;
		if (ioctl(fd, GPIO_GET_CHIPINFO_IOCTL, info) == 0 &&
		    strcmp(info->label, label) == 0)
			break;
		close(fd);
		fd = -1;
	}
	closedir(d);
	return fd;
}

/* Value of chip `label` line `off` as /sys/kernel/debug/gpio shows it:
 * 1 "hi", 0 "lo", -1 not found.  The chip section header reads
 * "gpiochipN: GPIOs A-B, parent: ..., LABEL:" and requested lines
 * " gpio-G (name|consumer) out hi". */
static int debugfs_value(const char *label, unsigned off)
{
	FILE *f = fopen("/sys/kernel/debug/gpio", "r");
	char line[512], want[300];
	int base = -1, v = -1;
	if (!f)
		return -1;
	snprintf(want, sizeof want, " %s:\n", label);
	while (fgets(line, sizeof line, f)) {
		if (strncmp(line, "gpiochip", 8) == 0) {
			char *g = strstr(line, "GPIOs ");
			char alt[320];
			snprintf(alt, sizeof alt, " %s, can sleep:", label);
			base = -1;
			if (g && (strstr(line, want) || strstr(line, alt)))
				base = atoi(g + 6);
		} else if (base >= 0 && strncmp(line, " gpio-", 6) == 0 &&
			   atoi(line + 6) == base + (int)off) {
			if (strstr(line, " out hi"))
				v = 1;
			else if (strstr(line, " out lo"))
				v = 0;
			break;
		}
	}
	fclose(f);
	return v;
}

static int sysfs_value(const char *file)
{
	FILE *f = fopen(file, "r");
	int v = -1;
	if (!f)
		return -1;
	if (fscanf(f, "%d", &v) != 1)
		v = -1;
	fclose(f);
	return v;
}

int main(int argc, char **argv)
{
	const char *label = NULL, *simfile = NULL, *consumer = "negobs-motor";
	int off = -1, opt, cfd;
	char path[300];
	struct gpiochip_info ci;
	struct gpio_v2_line_info li;
	struct gpio_v2_line_request req;
	static const int pattern[] = {1, 0, 1, 0};
	unsigned i;

	while ((opt = getopt(argc, argv, "l:o:s:c:")) != -1) {
		switch (opt) {
		case 'l':
			label = optarg;
			break;
		case 'o':
			off = atoi(optarg);
			break;
		case 's':
			simfile = optarg;
			break;
		case 'c':
			consumer = optarg;
			break;
		default:
			goto usage;
		}
	}
	if (!label || off < 0)
		goto usage;
	setvbuf(stdout, NULL, _IOLBF, 0);

	cfd = open_chip(label, path, sizeof path, &ci);
	if (cfd < 0) {
		printf("gpio_test: FAIL no /dev/gpiochip* with label '%s'\n",
		       label);
		return 1;
	}
	printf("gpio_test: %s name %s label '%s' lines %u, line %d, "
	       "observer %s\n",
	       path, ci.name, ci.label, ci.lines, off,
	       simfile ? simfile : "/sys/kernel/debug/gpio");
	if ((unsigned)off >= ci.lines) {
		printf("gpio_test: FAIL offset %d out of range\n", off);
		return 1;
	}

	memset(&req, 0, sizeof req);
	req.offsets[0] = (unsigned)off;
	req.num_lines = 1;
	snprintf(req.consumer, sizeof req.consumer, "%s", consumer);
	req.config.flags = GPIO_V2_LINE_FLAG_OUTPUT;
	req.config.num_attrs = 1;
	req.config.attrs[0].attr.id = GPIO_V2_LINE_ATTR_ID_OUTPUT_VALUES;
	req.config.attrs[0].attr.values = 0;
	req.config.attrs[0].mask = 1;
	if (ioctl(cfd, GPIO_V2_GET_LINE_IOCTL, &req) < 0) {
		printf("gpio_test: FAIL GPIO_V2_GET_LINE: %s\n",
		       strerror(errno));
		return 1;
	}

	memset(&li, 0, sizeof li);
	li.offset = (unsigned)off;
	CHECK(ioctl(cfd, GPIO_V2_GET_LINEINFO_IOCTL, &li) == 0 &&
		  (li.flags & GPIO_V2_LINE_FLAG_USED) &&
		  (li.flags & GPIO_V2_LINE_FLAG_OUTPUT) &&
		  strcmp(li.consumer, consumer) == 0,
	      "LINEINFO: used by '%s', output (flags 0x%llx)", li.consumer,
	      (unsigned long long)li.flags);

	for (i = 0; i < sizeof pattern / sizeof pattern[0]; i++) {
		struct gpio_v2_line_values lv;
		int got, obs;
		lv.bits = (unsigned)pattern[i];
		lv.mask = 1;
		if (ioctl(req.fd, GPIO_V2_LINE_SET_VALUES_IOCTL, &lv) < 0) {
			CHECK(0, "SET_VALUES %d: %s", pattern[i],
			      strerror(errno));
			continue;
		}
		lv.bits = 0;
		lv.mask = 1;
		got = ioctl(req.fd, GPIO_V2_LINE_GET_VALUES_IOCTL, &lv) == 0
			  ? (int)(lv.bits & 1)
			  : -1;
		obs = simfile ? sysfs_value(simfile)
			      : debugfs_value(ci.label, (unsigned)off);
		CHECK(got == pattern[i] && obs == pattern[i],
		      "set %d: chardev reads %d, observer reads %d", pattern[i],
		      got, obs);
	}
	close(req.fd);

	memset(&li, 0, sizeof li);
	li.offset = (unsigned)off;
	CHECK(ioctl(cfd, GPIO_V2_GET_LINEINFO_IOCTL, &li) == 0 &&
		  !(li.flags & GPIO_V2_LINE_FLAG_USED),
	      "line released after close (flags 0x%llx)",
	      (unsigned long long)li.flags);
	close(cfd);
	printf("gpio_test: %s\n", fails ? "FAIL" : "OK");
	return fails ? 1 : 0;
usage:
	fprintf(stderr, "usage: gpio_test -l LABEL -o OFFSET [-s SIMVALUE] "
			"[-c CONSUMER]\n");
	return 2;
}

/*
 * Guest-instruction counter for qemu-user (TCG plugin):
 *   qemu-aarch64 -plugin ./libnegobs_insn.so,out=FILE PROGRAM ...
 * writes the number of guest instructions PROGRAM executed to FILE (or to
 * qemu's log, stderr, without out=): a line "insns N", then one line
 * "fn N NAME" per guest function symbol, N the instructions of the blocks
 * that start in it (self cost, as callgrind's; inlined code counts in its
 * caller). Debian's qemu-user accepts plugins
 * but ships neither an example plugin nor the API header, so the few
 * declarations of the plugin API (version 1, QEMU 4.2 .. 7.x) that this
 * file uses are written out below. Each translated block adds its
 * instruction count inline to one counter when it runs, so the count is
 * exact for a single-threaded guest and costs little emulation speed.
 *
 * Built for the host by tools/negobs bench --aarch64:
 *   cc -shared -fPIC -O2 -o libnegobs_insn.so tools/qemu/insn_count.c
 */
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

/* ---- the plugin API, as QEMU 7.2 declares it ------------------------- */
typedef uint64_t qemu_plugin_id_t;
struct qemu_plugin_tb;
struct qemu_plugin_insn;
typedef struct qemu_info_t qemu_info_t; /* not read */
enum qemu_plugin_op { QEMU_PLUGIN_INLINE_ADD_U64 };
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id,
                                               struct qemu_plugin_tb *tb);
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);
void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id,
                                           qemu_plugin_vcpu_tb_trans_cb_t cb);
void qemu_plugin_register_vcpu_tb_exec_inline(struct qemu_plugin_tb *tb,
                                              enum qemu_plugin_op op,
                                              void *ptr, uint64_t imm);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
struct qemu_plugin_insn *qemu_plugin_tb_get_insn(
    const struct qemu_plugin_tb *tb, size_t idx);
const char *qemu_plugin_insn_symbol(const struct qemu_plugin_insn *insn);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id,
                                    qemu_plugin_udata_cb_t cb, void *userdata);
void qemu_plugin_outs(const char *string);

#define EXPORT __attribute__((visibility("default")))
EXPORT extern int qemu_plugin_version;
EXPORT int qemu_plugin_version = 1;
EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
                               int argc, char **argv);
/* ---------------------------------------------------------------------- */

#define NSYM 8192 /* open addressing on the symbol's address */

static uint64_t insns;
static char out_path[4096];
static const char *sym_name[NSYM];
static uint64_t sym_insns[NSYM];

/* The counter of a symbol (blocks without one share slot 0). */
static uint64_t *sym_counter(const char *name)
{
    size_t h;
    if (name == NULL) {
        return &sym_insns[0];
    }
    h = (size_t)(((uintptr_t)name >> 3) * 2654435761u) % NSYM;
    while (h == 0 || (sym_name[h] != NULL && sym_name[h] != name)) {
        h = (h + 1) % NSYM;
    }
    sym_name[h] = name;
    return &sym_insns[h];
}

static void tb_trans(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    size_t n = qemu_plugin_tb_n_insns(tb);
    (void)id;
    qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64,
                                             &insns, n);
    if (n > 0) {
        qemu_plugin_register_vcpu_tb_exec_inline(
            tb, QEMU_PLUGIN_INLINE_ADD_U64,
            sym_counter(
                qemu_plugin_insn_symbol(qemu_plugin_tb_get_insn(tb, 0))),
            n);
    }
}

static void at_exit(qemu_plugin_id_t id, void *userdata)
{
    char line[64];
    (void)id;
    (void)userdata;
    snprintf(line, sizeof line, "insns %" PRIu64 "\n", insns);
    if (out_path[0] != '\0') {
        FILE *f = fopen(out_path, "w");
        if (f != NULL) {
            size_t i;
            fputs(line, f);
            for (i = 1; i < NSYM; i++) {
                if (sym_name[i] != NULL) {
                    fprintf(f, "fn %" PRIu64 " %s\n", sym_insns[i],
                            sym_name[i]);
                }
            }
            fclose(f);
            return;
        }
    }
    qemu_plugin_outs(line);
}

int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info, int argc,
                        char **argv)
{
    int i;
    (void)info;
    for (i = 0; i < argc; i++) {
        if (strncmp(argv[i], "out=", 4) == 0) {
            snprintf(out_path, sizeof out_path, "%s", argv[i] + 4);
        }
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, tb_trans);
    qemu_plugin_register_atexit_cb(id, at_exit, NULL);
    return 0;
}

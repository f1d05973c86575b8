// SPDX-License-Identifier: GPL-2.0
/*
 * pwm-sim: a PWM chip with no hardware behind it, for emulated tests.
 *
 * Written for the Linux 6.1 PWM core API (struct pwm_ops .apply/.get_state
 * returning int).  It registers a platform device "pwm-sim" and a pwm_chip
 * with `npwm` channels.  .apply stores the requested state, .get_state hands
 * it back, so everything a user sees through /sys/class/pwm/pwmchipN and
 * /sys/kernel/debug/pwm is the real PWM core's behaviour (export/unexport,
 * EINVAL for duty_cycle > period, EBUSY, ...) on top of a recorded state.
 * Every applied state is also logged (pr_info) so the serial log shows it.
 *
 * Fault injection: while /sys/module/pwm_sim/parameters/fail_apply is 1,
 * .apply refuses every state with -EIO and keeps the old one, as a PWM
 * block whose bus write fails would; writes to duty_cycle then fail with
 * EIO in user space.
 */
#include <linux/err.h>
#include <linux/module.h>
#include <linux/platform_device.h>
#include <linux/pwm.h>
#include <linux/slab.h>

static unsigned int npwm = 2;
module_param(npwm, uint, 0444);
MODULE_PARM_DESC(npwm, "number of PWM channels (default 2)");

static bool fail_apply;
module_param(fail_apply, bool, 0644);
MODULE_PARM_DESC(fail_apply,
                 "1: every .apply fails with -EIO (fault injection)");

struct pwm_sim {
    struct pwm_chip chip;
    struct pwm_state *state; /* one recorded state per channel */
};

static struct platform_device *pwm_sim_pdev;

static inline struct pwm_sim *to_pwm_sim(struct pwm_chip *chip)
{
    return container_of(chip, struct pwm_sim, chip);
}

static int pwm_sim_apply(struct pwm_chip *chip, struct pwm_device *pwm,
                         const struct pwm_state *state)
{
    struct pwm_sim *sim = to_pwm_sim(chip);

    if (READ_ONCE(fail_apply)) {
        pr_info("pwm-sim: ch%u apply refused (fail_apply)\n", pwm->hwpwm);
        return -EIO;
    }
    sim->state[pwm->hwpwm] = *state;
    pr_info("pwm-sim: ch%u period=%llu duty=%llu polarity=%s enabled=%d\n",
            pwm->hwpwm, state->period, state->duty_cycle,
            state->polarity == PWM_POLARITY_NORMAL ? "normal" : "inversed",
            state->enabled);
    return 0;
}

static int pwm_sim_get_state(struct pwm_chip *chip, struct pwm_device *pwm,
                             struct pwm_state *state)
{
    *state = to_pwm_sim(chip)->state[pwm->hwpwm];
    return 0;
}

static const struct pwm_ops pwm_sim_ops = {
    .apply = pwm_sim_apply,
    .get_state = pwm_sim_get_state,
    .owner = THIS_MODULE,
};

static int pwm_sim_probe(struct platform_device *pdev)
{
    struct pwm_sim *sim;

    if (npwm == 0 || npwm > 64)
        return -EINVAL;
    sim = devm_kzalloc(&pdev->dev, sizeof(*sim), GFP_KERNEL);
    if (!sim)
        return -ENOMEM;
    sim->state = devm_kcalloc(&pdev->dev, npwm, sizeof(*sim->state),
                              GFP_KERNEL);
    if (!sim->state)
        return -ENOMEM;
    sim->chip.dev = &pdev->dev;
    sim->chip.ops = &pwm_sim_ops;
    sim->chip.npwm = npwm;
    sim->chip.base = -1;
    return devm_pwmchip_add(&pdev->dev, &sim->chip);
}

static struct platform_driver pwm_sim_driver = {
    .probe = pwm_sim_probe,
    .driver =
        {
            .name = "pwm-sim",
        },
};

static int __init pwm_sim_init(void)
{
    int ret = platform_driver_register(&pwm_sim_driver);

    if (ret)
        return ret;
    pwm_sim_pdev = platform_device_register_simple("pwm-sim", -1, NULL, 0);
    if (IS_ERR(pwm_sim_pdev)) {
        platform_driver_unregister(&pwm_sim_driver);
        return PTR_ERR(pwm_sim_pdev);
    }
    return 0;
}

static void __exit pwm_sim_exit(void)
{
    platform_device_unregister(pwm_sim_pdev);
    platform_driver_unregister(&pwm_sim_driver);
}

module_init(pwm_sim_init);
module_exit(pwm_sim_exit);
MODULE_DESCRIPTION("Simulated PWM chip for emulated negobs tests");
MODULE_LICENSE("GPL");

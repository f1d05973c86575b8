/* Every public header of lib/ and port/ in one unit: no name may clash. */
#include "negobs/negobs.h"
#include "negobs_port/motor.h"
#include "negobs_port/camera.h"
#include "negobs_port/camera_v4l2.h"
#include "negobs_port/camera_replay.h"
#include "negobs_port/clock.h"
#include "negobs_port/input.h"
int main(void)
{
    return 0;
}

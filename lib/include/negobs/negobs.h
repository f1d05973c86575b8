/* negobs umbrella header: includes every public header of the core. */
#ifndef NEGOBS_NEGOBS_H
#define NEGOBS_NEGOBS_H

#include "negobs/status.h"
#include "negobs/fixed.h"
#include "negobs/image.h"
#include "negobs/boxsum.h"
#include "negobs/version.h"
#include "negobs/stereo.h"
#include "negobs/depth.h"
#include "negobs/ground.h"
#include "negobs/verdict.h"
#include "negobs/detect.h"
#include "negobs/alert.h"
#include "negobs/rectify.h"
#include "negobs/valign.h"
#include "negobs/pipeline.h"

#endif /* NEGOBS_NEGOBS_H */

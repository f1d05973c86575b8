/* cmocka needs these system headers first, in this order. */
#ifndef NEGOBS_TEST_CMOCKA_ALL_H
#define NEGOBS_TEST_CMOCKA_ALL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "test_rng.h"

#endif

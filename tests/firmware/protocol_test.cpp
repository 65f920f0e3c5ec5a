#include "fw_bench.h"

#include "scenarios/bound/bound.h"

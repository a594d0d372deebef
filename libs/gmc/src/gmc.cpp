#include "gmc/gmc/gmc.h"

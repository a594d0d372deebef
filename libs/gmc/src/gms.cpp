#include "gmc/gmc/gms.h"

// Compiled with the material layer's include path by the test layers_accept_downward_include, the
// control of layers_reject_backward_include: the same target does see every layer below it.
#include "btf/compress/vq_btf.h"
#include "btf/core/warp.h"
#include "btf/io/merl.h"
#include "btf/material/material.h"

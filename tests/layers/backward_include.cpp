// Compiled with the material layer's include path by the test layers_reject_backward_include, which
// passes only when the compiler cannot find the render layer's header: a layer sees the layers
// below it and never the ones above (libbtf/CMakeLists.txt).
#include "btf/render/scene.h"

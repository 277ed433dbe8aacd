// mosaic/mosaic.hpp — the whole public API of mosaic, a SIMD multithreaded tile-based
// software rasterizer. See README.md for the pipeline and conventions.
#pragma once

#include "mosaic/draw.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/occlusion.hpp"
#include "mosaic/render_target.hpp"
#include "mosaic/renderer.hpp"
#include "mosaic/scene.hpp"
#include "mosaic/shader.hpp"
#include "mosaic/texture.hpp"
#include "mosaic/types.hpp"

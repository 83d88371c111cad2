// vtkDirectSurfaceMapper's OpenGL resources and drawing: per view (a window's renderer and an
// actor), the textures a cast image is uploaded to and the full-screen quad that draws them with
// their exact depth (gl_FragDepth), upsampled edge- and depth-aware for a reduced image; and the
// opaque depth read back under translucent surfaces.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"

#include <string>

namespace
{
/// The colour and depth images drawn by a full-screen quad: colour as RGBA8, window depth as
/// R32F; a depth of 1 (a miss) is discarded. An image of the viewport's size is drawn pixel for
/// pixel; a smaller one (interaction) is upsampled edge- and depth-aware (`upsample`).
const char* const kQuadDeclarations = R"(
uniform sampler2D colorTexture;
uniform sampler2D depthTexture;
uniform int upsample;

// Window depth of the cast pixel p; 2 outside the image (a miss is 1).
float castDepth(ivec2 p)
{
  ivec2 size = textureSize(depthTexture, 0);
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size)))
  {
    return 2.0;
  }
  return texelFetch(depthTexture, p, 0).r;
}

// Whether cast pixel n (depth dn) and its neighbour n + o (depth dt) show one surface, judged
// from the four depths along the line through them: n - o, n, n + o, n + 2o. A continuous
// surface changes its depth by similar steps from pixel to pixel; a silhouette or a depth
// discontinuity between n and n + o is a step out of line with those on both sides of it (also
// for a feature one pixel wide: the step beyond it is the other surface's own). So the step is
// one surface's when it is at most twice the smaller step beside it (the tolerance scales with
// the local depth slope: steep and flat surfaces alike), or, where the slope itself changes
// (near a depth extremum the steps shrink towards 0), when the two second differences agree in
// sign and size, as a smooth curve's do (a jump makes them opposite). A side that is a miss or
// outside the image says nothing. 2^-20 covers the rounding of float depths (24-bit mantissa)
// below 1.
bool sameSurface(ivec2 n, ivec2 o, float dn, float dt)
{
  if (dt >= 1.0)
  {
    return false;
  }
  float before = castDepth(n - o);
  float after = castDepth(n + 2 * o);
  float step = dt - dn;
  float besideStep = 0.0; // (0 when neither side tells: then only equal depths pass)
  if (before < 1.0 && after < 1.0)
  {
    besideStep = min(abs(dn - before), abs(after - dt));
  }
  else if (before < 1.0)
  {
    besideStep = abs(dn - before);
  }
  else if (after < 1.0)
  {
    besideStep = abs(after - dt);
  }
  if (abs(step) <= 2.0 * besideStep + 1.0 / 1048576.0)
  {
    return true;
  }
  if (before >= 1.0 || after >= 1.0)
  {
    return false;
  }
  float curveBefore = step - (dn - before);
  float curveAfter = (after - dt) - step;
  return curveBefore * curveAfter > 0.0 &&
    abs(curveAfter - curveBefore) <= 0.5 * (abs(curveBefore) + abs(curveAfter));
}
)";
const char* const kQuadImplementation = R"(
  if (upsample == 0)
  {
    float depth = texture(depthTexture, texCoord).r;
    if (depth >= 1.0) { discard; }
    gl_FragDepth = depth;
    gl_FragData[0] = texture(colorTexture, texCoord);
  }
  else
  {
    // A joint bilateral filter: the bilinear weights of the 2 x 2 cast pixels around this one,
    // keeping only those on the nearest cast pixel's surface, so that colour and depth never
    // blend across a silhouette or a depth discontinuity and a miss never contributes. The
    // nearest cast pixel decides coverage: silhouettes stay as the cast has them.
    ivec2 size = textureSize(depthTexture, 0);
    vec2 castPoint = texCoord * vec2(size); // cast pixel k spans [k, k + 1)
    ivec2 nearest = min(ivec2(castPoint), size - 1);
    float nearestDepth = texelFetch(depthTexture, nearest, 0).r;
    if (nearestDepth >= 1.0) { discard; }
    ivec2 corner = ivec2(floor(castPoint - 0.5));
    vec2 f = castPoint - 0.5 - vec2(corner);
    vec4 color = vec4(0.0);
    float depth = 0.0;
    float weight = 0.0;
    for (int k = 0; k < 4; ++k)
    {
      ivec2 offset = ivec2(k & 1, k >> 1);
      ivec2 p = clamp(corner + offset, ivec2(0), size - 1);
      float d = texelFetch(depthTexture, p, 0).r;
      if (p == nearest || sameSurface(nearest, p - nearest, nearestDepth, d))
      {
        vec2 axes = mix(1.0 - f, f, vec2(offset));
        float w = axes.x * axes.y;
        color += w * texelFetch(colorTexture, p, 0);
        depth += w * d;
        weight += w;
      }
    }
    // (weight > 0: the nearest cast pixel's bilinear weight is at least 1/4.)
    gl_FragDepth = depth / weight;
    gl_FragData[0] = color / weight;
  }
)";
}

//------------------------------------------------------------------------------
vtkDirectSurfaceMapper::Internals::ViewResources& vtkDirectSurfaceMapper::Internals::ResourcesOf(
  vtkOpenGLRenderWindow* window, vtkRenderer* renderer, vtkActor* actor)
{
  for (auto it = this->Views.begin(); it != this->Views.end();)
  {
    ViewResources& r = **it;
    if (!r.Window || !r.Renderer || !r.Actor)
    {
      if (r.Window)
      {
        r.Release(r.Window);
      }
      it = this->Views.erase(it);
    }
    else if (r.Window == window && r.Renderer == renderer && r.Actor == actor)
    {
      return r;
    }
    else
    {
      ++it;
    }
  }
  this->Views.emplace_back(new ViewResources);
  ViewResources& made = *this->Views.back();
  made.Window = window;
  made.Renderer = renderer;
  made.Actor = actor;
  return made;
}

void vtkDirectSurfaceMapper::Internals::ViewResources::Release(vtkWindow* window)
{
  this->Refining.reset();
  for (auto* texture : { &this->Selection.IdTexture, &this->Selection.DepthTexture })
  {
    if (*texture)
    {
      (*texture)->ReleaseGraphicsResources(window);
      *texture = nullptr;
    }
  }
  this->Selection.Signature.clear();
  if (this->Quad)
  {
    this->Quad->ReleaseGraphicsResources(window);
    this->Quad.reset();
  }
  for (auto* texture : { &this->ColorTexture, &this->DepthTexture })
  {
    if (*texture)
    {
      (*texture)->ReleaseGraphicsResources(window);
      *texture = nullptr;
    }
  }
  this->TexturesValid = false;
  this->Signature.clear();
}

double vtkDirectSurfaceMapper::Internals::ReadOpaqueDepth(const Frame& frame)
{
  const int* viewport = frame.Viewport;
  this->OpaqueDepth.resize(static_cast<std::size_t>(viewport[2]) * viewport[3]);
  {
    vtkOpenGLState::ScopedglEnableDisable savedScissor(frame.Window->GetState(), GL_SCISSOR_TEST);
    frame.Window->GetZbufferData(viewport[0], viewport[1], viewport[0] + viewport[2] - 1,
      viewport[1] + viewport[3] - 1, this->OpaqueDepth.data());
  }
  double sum = 0.0;
  for (float z : this->OpaqueDepth)
  {
    sum = sum * 1.000001 + z;
  }
  return sum;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::Internals::LoadTextures(vtkOpenGLRenderWindow* window,
  vtkSmartPointer<vtkTextureObject>& color, vtkSmartPointer<vtkTextureObject>& depth, int width,
  int height, const std::uint8_t* colors, const float* depths)
{
  for (auto* texture : { &color, &depth })
  {
    if (!*texture)
    {
      *texture = vtkSmartPointer<vtkTextureObject>::New();
      (*texture)->SetMinificationFilter(vtkTextureObject::Nearest);
      (*texture)->SetMagnificationFilter(vtkTextureObject::Nearest);
      (*texture)->SetWrapS(vtkTextureObject::ClampToEdge);
      (*texture)->SetWrapT(vtkTextureObject::ClampToEdge);
    }
    (*texture)->SetContext(window);
  }
  // (Create2DFromRaw only reads the pixels; its parameter is not const.)
  color->Create2DFromRaw(width, height, 4, VTK_UNSIGNED_CHAR, const_cast<std::uint8_t*>(colors));
  depth->Create2DFromRaw(width, height, 1, VTK_FLOAT, const_cast<float*>(depths));
}

void vtkDirectSurfaceMapper::Internals::Upload(ViewResources& gl, vtkOpenGLRenderWindow* window,
  const ImageCast& images, int width, int height, double sampleDistance)
{
  LoadTextures(window, gl.ColorTexture, gl.DepthTexture, width, height, images.Colors.data(),
    images.WindowDepth.data());
  gl.TexturesValid = true;
  gl.ImageSize[0] = width;
  gl.ImageSize[1] = height;
  gl.ImageSampleDistance = sampleDistance;
}

bool vtkDirectSurfaceMapper::Internals::Draw(
  ViewResources& gl, vtkOpenGLRenderWindow* window, bool translucent, const int viewport[4])
{
  return DrawTextures(gl, window, translucent, viewport, gl.ColorTexture, gl.DepthTexture,
    gl.ImageSize[0] != viewport[2] || gl.ImageSize[1] != viewport[3]);
}

bool vtkDirectSurfaceMapper::Internals::DrawTextures(ViewResources& gl,
  vtkOpenGLRenderWindow* window, bool translucent, const int viewport[4], vtkTextureObject* color,
  vtkTextureObject* depth, bool upsample)
{
  if (!gl.Quad)
  {
    std::string fragment = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
    vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Decl", kQuadDeclarations);
    vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Impl", kQuadImplementation);
    gl.Quad.reset(new vtkOpenGLQuadHelper(window,
      vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fragment.c_str(), ""));
  }
  else
  {
    window->GetShaderCache()->ReadyShaderProgram(gl.Quad->Program);
  }
  if (!gl.Quad->Program || !gl.Quad->Program->GetCompiled())
  {
    return false;
  }
  vtkOpenGLState* state = window->GetState();
  vtkOpenGLState::ScopedglDepthFunc savedDepthFunc(state);
  vtkOpenGLState::ScopedglDepthMask savedDepthMask(state);
  vtkOpenGLState::ScopedglEnableDisable savedDepthTest(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglEnableDisable savedBlend(state, GL_BLEND);
  vtkOpenGLState::ScopedglBlendFuncSeparate savedBlendFunction(state);
  vtkOpenGLState::ScopedglViewport savedViewport(state);
  vtkOpenGLState::ScopedglEnableDisable savedScissor(state, GL_SCISSOR_TEST);
  if (translucent)
  {
    // Over the finished frame: already limited to the opaque depth, blended, no depth write.
    state->vtkglViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    state->vtkglDisable(GL_SCISSOR_TEST);
    state->vtkglDisable(GL_DEPTH_TEST);
    state->vtkglDepthMask(GL_FALSE);
    state->vtkglEnable(GL_BLEND);
    state->vtkglBlendFuncSeparate(
      GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  }
  else
  {
    // In the opaque pass: depth-tested against, and written for, every other prop.
    state->vtkglEnable(GL_DEPTH_TEST);
    state->vtkglDepthFunc(GL_LEQUAL);
    state->vtkglDepthMask(GL_TRUE);
  }
  color->Activate();
  depth->Activate();
  gl.Quad->Program->SetUniformi("colorTexture", color->GetTextureUnit());
  gl.Quad->Program->SetUniformi("depthTexture", depth->GetTextureUnit());
  // Full resolution is drawn texel for texel, exactly as cast.
  gl.Quad->Program->SetUniformi("upsample", upsample ? 1 : 0);
  gl.Quad->Render();
  depth->Deactivate();
  color->Deactivate();
  return true;
}

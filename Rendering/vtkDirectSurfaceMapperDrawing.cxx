// vtkDirectSurfaceMapper's OpenGL resources and drawing: per view (a window's renderer and an
// actor), the textures a cast image is uploaded to and the full-screen quads that draw them with
// their exact depth (gl_FragDepth), a reduced image upsampled without blending across
// silhouettes (the core's render/Upsampling maps, as two more textures); the opaque depth read
// back under translucent surfaces; the renderer's FXAA moved after them; under screen-space
// ambient occlusion, each pixel's view-space position and normal into the pass's G-buffer; and
// in a multisampled framebuffer, each pixel's sample mask.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkCommand.h"
#include "vtkFXAAOptions.h"
#include "vtkOpenGLFXAAFilter.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderer.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkShaderProgram.h"

#include <algorithm>
#include <functional>
#include <string>

namespace
{
/// The colour and depth images drawn by full-screen quads: colour as RGBA8, window depth as
/// R32F; a depth of 1 (a miss) is discarded. An image of the viewport's size is drawn pixel for
/// pixel (kQuadFull); a smaller one (interaction) is upsampled without blending across
/// silhouettes, by the core's rule (tetdsr/render/Upsampling.h), in two draws: the blocks of
/// 2 x 2 cast pixels on one surface filtered bilinearly by the texture unit (kQuadSurface), then
/// the blocks with a silhouette or a miss, where each output pixel keeps only the corners on its
/// nearest cast pixel's surface (the masks' bits) and the nearest cast pixel decides coverage
/// (kQuadMixed). Three programs without branches between them: a software rasteriser (Mesa's
/// llvmpipe) runs both sides of a branch, so one program with all three cost an interactive
/// frame at 1024 x 1024 about 20 ms more than these.
const char* const kQuadDeclarations = R"(
uniform sampler2D colorTexture;
uniform sampler2D depthTexture;
)";
const char* const kQuadUpsampleDeclarations = R"(
uniform sampler2D colorTexture;
uniform sampler2D depthTexture;
uniform sampler2D maskTexture;
uniform sampler2D blockTexture;

int byteAt(sampler2D bytes, ivec2 p)
{
  return int(texelFetch(bytes, p, 0).r * 255.0 + 0.5);
}
)";
const char* const kQuadFull = R"(
  ivec2 nearest = min(ivec2(texCoord * vec2(textureSize(depthTexture, 0))),
    textureSize(depthTexture, 0) - 1);
  float depth = texelFetch(depthTexture, nearest, 0).r;
  if (depth >= 1.0) { discard; }
  gl_FragDepth = depth;
  gl_FragData[0] = texelFetch(colorTexture, nearest, 0);
)";
const char* const kQuadUpsample = R"(
  ivec2 size = textureSize(depthTexture, 0);
  vec2 castPoint = texCoord * vec2(size); // cast pixel k spans [k, k + 1)
  ivec2 corner = ivec2(floor(castPoint - 0.5));
  int block = byteAt(blockTexture, corner + 1);
  if (block == 2) { discard; } // every corner a miss
  // One surface (block 1): the texture unit's bilinear filter.
  vec4 color = texture(colorTexture, texCoord);
  float depth = texture(depthTexture, texCoord).r;
  // A silhouette or a miss among the corners (block 0): only the corners on the nearest cast
  // pixel's surface. (A loop run once or never, not an if: a software rasteriser such as Mesa's
  // llvmpipe runs both sides of an if for every pixel, but leaves a loop that no pixel of its
  // group enters.)
  for (int mixed = block == 0 ? 1 : 0; mixed > 0; --mixed)
  {
    ivec2 nearest = min(ivec2(castPoint), size - 1);
    float nearestDepth = texelFetch(depthTexture, nearest, 0).r;
    if (nearestDepth >= 1.0) { discard; }
    int mask = byteAt(maskTexture, nearest);
    vec2 f = castPoint - 0.5 - vec2(corner);
    color = vec4(0.0);
    depth = 0.0;
    float weight = 0.0;
    for (int k = 0; k < 4; ++k)
    {
      ivec2 offset = ivec2(k & 1, k >> 1);
      ivec2 p = clamp(corner + offset, ivec2(0), size - 1);
      ivec2 o = p - nearest; // each component in -1..1
      int bit = (o.y + 1) * 3 + (o.x + 1);
      if (bit == 4 || ((mask >> (bit < 4 ? bit : bit - 1)) & 1) != 0)
      {
        vec2 axes = mix(1.0 - f, f, vec2(offset));
        float w = axes.x * axes.y;
        color += w * texelFetch(colorTexture, p, 0);
        depth += w * texelFetch(depthTexture, p, 0).r;
        weight += w;
      }
    }
    // (weight > 0: the nearest cast pixel's bilinear weight is at least 1/4.)
    color /= weight;
    depth /= weight;
  }
  gl_FragDepth = depth;
  gl_FragData[0] = color;
)";
/// Appended to either quad under screen-space ambient occlusion: what vtkSSAOPass's G-buffer
/// holds for polygons (vtkOpenGLPolyDataMapper's vertexVC and normalVCVSOutput): the pixel's
/// view-space position, from its window position and depth through the inverse projection, and
/// its normal turned to the viewer, from the nearest cast pixel's normal.
const char* const kViewSpaceDeclarations = R"(
uniform sampler2D normalTexture;
uniform mat4 ndcToView;
uniform mat3 normalToView;
)";
const char* const kViewSpace = R"(
  vec4 pointVC = ndcToView * vec4(2.0 * texCoord - 1.0, 2.0 * depth - 1.0, 1.0);
  vec3 positionVC = pointVC.xyz / pointVC.w;
  ivec2 normalSize = textureSize(normalTexture, 0);
  vec3 normalVC = normalize(normalToView *
    texelFetch(normalTexture, min(ivec2(texCoord * vec2(normalSize)), normalSize - 1), 0).xyz);
  normalVC = dot(normalVC, positionVC) > 0.0 ? -normalVC : normalVC;
  gl_FragData[1] = vec4(positionVC, 1.0);
  gl_FragData[2] = vec4(normalVC, 1.0);
)";
/// Appended to the full-resolution quad in a multisampled framebuffer: the samples of the pixel
/// that see the surface (tetdsr/render/Multisampling.h), so that its silhouette is smoothed as
/// polygons' are. (gl_SampleMask: GLSL 4.0, or this extension to VTK's GLSL 1.50.)
const char* const kSampleMaskExtension =
  "//VTK::System::Dec\n#extension GL_ARB_sample_shading : require\n";
const char* const kSampleMaskDeclarations = R"(
uniform sampler2D sampleMaskTexture;
)";
const char* const kSampleMask = R"(
  gl_SampleMask[0] = int(texelFetch(sampleMaskTexture, nearest, 0).r * 255.0 + 0.5);
)";
}

//------------------------------------------------------------------------------
std::vector<glm::dvec2> vtkDirectSurfaceMapper::Internals::SamplePositions()
{
  std::vector<glm::dvec2> positions;
  if (!GLEW_ARB_sample_shading) // (the quad's gl_SampleMask: none, one ray a pixel as before)
  {
    return positions;
  }
  GLint samples = 0;
  glGetIntegerv(GL_SAMPLES, &samples);
  for (GLint k = 0; samples > 1 && samples <= tetdsr::kMaxCoverageSamples && k < samples; ++k)
  {
    GLfloat position[2] = { 0.5f, 0.5f };
    glGetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(k), position);
    positions.emplace_back(position[0], position[1]);
  }
  return positions;
}

//------------------------------------------------------------------------------
vtkDirectSurfaceMapper::Internals::ViewResources& vtkDirectSurfaceMapper::Internals::ResourcesOf(
  vtkOpenGLRenderWindow* window, vtkRenderer* renderer, vtkActor* actor, int eye)
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
    else if (r.Window == window && r.Renderer == renderer && r.Actor == actor && r.Eye == eye)
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
  made.Eye = eye;
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
  for (auto& quad : this->Quads)
  {
    if (quad)
    {
      quad->ReleaseGraphicsResources(window);
      quad.reset();
    }
  }
  for (auto* texture : { &this->ColorTexture, &this->DepthTexture, &this->NormalTexture,
         &this->SampleMaskTexture, &this->MaskTexture, &this->BlockTexture })
  {
    if (*texture)
    {
      (*texture)->ReleaseGraphicsResources(window);
      *texture = nullptr;
    }
  }
  this->TexturesValid = false;
  this->NormalsValid = false;
  this->SampleMasksValid = false;
  this->UpsamplingValid = false;
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
void vtkDirectSurfaceMapper::Internals::Ready(
  vtkSmartPointer<vtkTextureObject>& texture, vtkOpenGLRenderWindow* window, int filter)
{
  if (!texture)
  {
    texture = vtkSmartPointer<vtkTextureObject>::New();
    texture->SetMinificationFilter(filter);
    texture->SetMagnificationFilter(filter);
    texture->SetWrapS(vtkTextureObject::ClampToEdge);
    texture->SetWrapT(vtkTextureObject::ClampToEdge);
  }
  texture->SetContext(window);
}

void vtkDirectSurfaceMapper::Internals::LoadTextures(vtkOpenGLRenderWindow* window,
  vtkSmartPointer<vtkTextureObject>& color, vtkSmartPointer<vtkTextureObject>& depth, int width,
  int height, const std::uint8_t* colors, const float* depths, int filter)
{
  Ready(color, window, filter);
  Ready(depth, window, filter);
  // (Create2DFromRaw only reads the pixels; its parameter is not const.)
  color->Create2DFromRaw(width, height, 4, VTK_UNSIGNED_CHAR, const_cast<std::uint8_t*>(colors));
  depth->Create2DFromRaw(width, height, 1, VTK_FLOAT, const_cast<float*>(depths));
}

void vtkDirectSurfaceMapper::Internals::LoadUpsampling(
  ViewResources& gl, vtkOpenGLRenderWindow* window, const float* depth, int width, int height)
{
  tetdsr::upsampleMaps(depth, width, height, gl.Upsampling,
    [](tetdsr::NodeId count, const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
      vtkSMPTools::For(0, count, [&](vtkIdType begin, vtkIdType end) { body(begin, end); });
    });
  Ready(gl.MaskTexture, window);
  Ready(gl.BlockTexture, window);
  gl.MaskTexture->Create2DFromRaw(
    width, height, 1, VTK_UNSIGNED_CHAR, gl.Upsampling.masks.data());
  gl.BlockTexture->Create2DFromRaw(
    width + 1, height + 1, 1, VTK_UNSIGNED_CHAR, gl.Upsampling.blocks.data());
  gl.UpsamplingValid = true;
}

void vtkDirectSurfaceMapper::Internals::Upload(ViewResources& gl, vtkOpenGLRenderWindow* window,
  const ImageCast& images, int width, int height, double sampleDistance, bool normals)
{
  LoadTextures(window, gl.ColorTexture, gl.DepthTexture, width, height, images.Colors.data(),
    images.WindowDepth.data(), vtkTextureObject::Linear);
  gl.SampleMasksValid =
    images.SampleMasks.size() == static_cast<std::size_t>(width) * height && sampleDistance == 1.0;
  if (gl.SampleMasksValid)
  {
    Ready(gl.SampleMaskTexture, window);
    gl.SampleMaskTexture->Create2DFromRaw(
      width, height, 1, VTK_UNSIGNED_CHAR, const_cast<std::uint8_t*>(images.SampleMasks.data()));
  }
  gl.NormalsValid = normals;
  if (normals)
  {
    const std::vector<float> unit(images.Normals.begin(), images.Normals.end());
    Ready(gl.NormalTexture, window);
    gl.NormalTexture->Create2DFromRaw(
      width, height, 3, VTK_FLOAT, const_cast<float*>(unit.data()));
  }
  gl.UpsamplingValid = false;
  if (sampleDistance > 1.0) // (a cast of the viewport's size is drawn texel for texel)
  {
    LoadUpsampling(gl, window, images.WindowDepth.data(), width, height);
  }
  gl.TexturesValid = true;
  gl.ImageSize[0] = width;
  gl.ImageSize[1] = height;
  gl.ImageSampleDistance = sampleDistance;
}

bool vtkDirectSurfaceMapper::Internals::Draw(ViewResources& gl, vtkOpenGLRenderWindow* window,
  bool translucent, const int viewport[4], const vtkDirectSurfaceViewSpace* viewSpace)
{
  // (An image of another size without its upsampling, which no Upload makes, is drawn from
  // its nearest cast pixels.)
  const bool upsample = gl.ImageSize[0] != viewport[2] || gl.ImageSize[1] != viewport[3];
  return DrawTextures(gl, window, translucent, viewport, gl.ColorTexture, gl.DepthTexture,
    upsample && gl.UpsamplingValid, gl.NormalsValid ? viewSpace : nullptr,
    !upsample && !translucent && gl.SampleMasksValid);
}

bool vtkDirectSurfaceMapper::Internals::ReadyQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad,
  vtkOpenGLRenderWindow* window, const char* declarations, const char* implementation,
  const char* system)
{
  if (!quad)
  {
    std::string fragment = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
    if (system)
    {
      vtkShaderProgram::Substitute(fragment, "//VTK::System::Dec", system);
    }
    vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Decl", declarations);
    vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Impl", implementation);
    quad.reset(new vtkOpenGLQuadHelper(window,
      vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fragment.c_str(), ""));
  }
  return quad->Program && quad->Program->GetCompiled();
}

bool vtkDirectSurfaceMapper::Internals::DrawTextures(ViewResources& gl,
  vtkOpenGLRenderWindow* window, bool translucent, const int viewport[4], vtkTextureObject* color,
  vtkTextureObject* depth, bool upsample, const vtkDirectSurfaceViewSpace* viewSpace,
  bool sampleMask)
{
  sampleMask = sampleMask && !upsample;
  const int k = (upsample ? 1 : 0) + (viewSpace ? 2 : 0) + (sampleMask ? 4 : 0);
  std::string declarations = upsample ? kQuadUpsampleDeclarations : kQuadDeclarations;
  std::string implementation = upsample ? kQuadUpsample : kQuadFull;
  if (viewSpace)
  {
    declarations += kViewSpaceDeclarations;
    implementation += kViewSpace;
  }
  if (sampleMask)
  {
    declarations += kSampleMaskDeclarations;
    implementation += kSampleMask;
  }
  if (!ReadyQuad(gl.Quads[k], window, declarations.c_str(), implementation.c_str(),
        sampleMask ? kSampleMaskExtension : nullptr))
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
  if (upsample)
  {
    gl.MaskTexture->Activate();
    gl.BlockTexture->Activate();
  }
  // Full resolution is drawn texel for texel, exactly as cast.
  vtkShaderProgram* program = gl.Quads[k]->Program;
  window->GetShaderCache()->ReadyShaderProgram(program);
  program->SetUniformi("colorTexture", color->GetTextureUnit());
  program->SetUniformi("depthTexture", depth->GetTextureUnit());
  if (upsample)
  {
    program->SetUniformi("maskTexture", gl.MaskTexture->GetTextureUnit());
    program->SetUniformi("blockTexture", gl.BlockTexture->GetTextureUnit());
  }
  // Under ambient occlusion the pass has three colour attachments bound, and activates them
  // only for polygon mappers (vtkSSAOPass::SetShaderParameters): the quad activates them itself.
  unsigned int attachments[3] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
    GL_COLOR_ATTACHMENT2 };
  if (sampleMask)
  {
    gl.SampleMaskTexture->Activate();
    program->SetUniformi("sampleMaskTexture", gl.SampleMaskTexture->GetTextureUnit());
  }
  if (viewSpace)
  {
    gl.NormalTexture->Activate();
    program->SetUniformi("normalTexture", gl.NormalTexture->GetTextureUnit());
    const glm::mat4 ndcToView(viewSpace->NdcToView);
    const glm::mat3 normalToView(viewSpace->NormalToView);
    program->SetUniformMatrix4x4("ndcToView", const_cast<float*>(&ndcToView[0][0]));
    program->SetUniformMatrix3x3("normalToView", const_cast<float*>(&normalToView[0][0]));
    state->vtkglDrawBuffers(3, attachments);
  }
  gl.Quads[k]->Render();
  if (viewSpace)
  {
    state->vtkglDrawBuffers(1, attachments);
    gl.NormalTexture->Deactivate();
  }
  if (sampleMask)
  {
    gl.SampleMaskTexture->Deactivate();
  }
  if (upsample)
  {
    gl.BlockTexture->Deactivate();
    gl.MaskTexture->Deactivate();
  }
  depth->Deactivate();
  color->Deactivate();
  return true;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::PostponeFXAA(vtkRenderer* renderer)
{
  if (!renderer || !renderer->GetUseFXAA() || !vtkOpenGLRenderer::SafeDownCast(renderer))
  {
    return; // (off, or already postponed this frame: depth peeling asks once per peel)
  }
  auto& postponed = this->Internal->PostponedFXAAs;
  postponed.erase(std::remove_if(postponed.begin(), postponed.end(),
                    [](const Internals::PostponedFXAA& entry) { return !entry.Renderer; }),
    postponed.end());
  auto entry = std::find_if(postponed.begin(), postponed.end(),
    [renderer](const Internals::PostponedFXAA& e) { return e.Renderer == renderer; });
  if (entry == postponed.end())
  {
    Internals::PostponedFXAA added;
    added.Renderer = renderer;
    // After the translucent surfaces' draws (priority 1: DrawDeferred, and the callers of
    // DrawTranslucentAcrossProcesses), before a compositor's observers (priority 0).
    added.ObserverTag = renderer->AddObserver(
      vtkCommand::EndEvent, this, &vtkDirectSurfaceMapper::ApplyPostponedFXAA, 0.5);
    postponed.push_back(added);
    entry = postponed.end() - 1;
  }
  entry->Due = true;
  renderer->SetUseFXAA(false);
}

void vtkDirectSurfaceMapper::ApplyPostponedFXAA(vtkObject* object, unsigned long, void*)
{
  auto* renderer = vtkOpenGLRenderer::SafeDownCast(object);
  if (!renderer)
  {
    return;
  }
  for (auto& entry : this->Internal->PostponedFXAAs)
  {
    if (entry.Renderer != renderer || !entry.Due)
    {
      continue;
    }
    entry.Due = false;
    renderer->SetUseFXAA(true);
    if (!entry.Filter)
    {
      entry.Filter = vtkSmartPointer<vtkOpenGLFXAAFilter>::New();
    }
    // As vtkOpenGLRenderer applies it: the renderer's options, over its viewport of the frame
    // (the filter draws into the current GL viewport, which its passes may have left another).
    if (vtkFXAAOptions* options = renderer->GetFXAAOptions())
    {
      entry.Filter->UpdateConfiguration(options);
    }
    vtkOpenGLState* state = renderer->GetState();
    vtkOpenGLState::ScopedglViewport savedViewport(state);
    vtkOpenGLState::ScopedglScissor savedScissor(state);
    int width, height, x, y;
    renderer->GetTiledSizeAndOrigin(&width, &height, &x, &y);
    state->vtkglViewport(x, y, width, height);
    state->vtkglScissor(x, y, width, height);
    entry.Filter->Execute(renderer);
  }
}

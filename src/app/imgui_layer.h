// Dear ImGui on a GLFW window: context, the GLFW platform backend and the OpenGL 3
// renderer backend (both built from Debian's libimgui-dev sources), one frame at a
// time. The renderer backend is compiled against our glad loader
// (IMGUI_IMPL_OPENGL_LOADER_CUSTOM), so one GL function table serves everything.
//
// The window's own input callbacks, installed before this layer, keep working: the
// backend calls them after its own. No imgui.ini is written.
#ifndef VOXGI_APP_IMGUI_LAYER_H
#define VOXGI_APP_IMGUI_LAYER_H

struct GLFWwindow;

namespace voxgi::app {

class ImGuiLayer {
 public:
  explicit ImGuiLayer(GLFWwindow* window);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  void beginFrame();
  // Draws the frame's lists into the default framebuffer over what is there.
  void endFrame();
  // Whether the panel has the keyboard (a text field) or the mouse (over a window).
  bool wantsKeyboard() const;
  bool wantsMouse() const;
};

}  // namespace voxgi::app

#endif  // VOXGI_APP_IMGUI_LAYER_H

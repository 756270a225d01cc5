// SPDX-License-Identifier: MIT
#include "viewer/viewer_app.h"

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "harness/interrupt.h"
#include "harness/report/pictures.h"
#include "models/model_registry.h"
#include "render/offscreen_context.h"
#include "render/surface_frame.h"
#include "render/surface_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <stdexcept>

namespace softbench::viewer {
namespace {

using Clock = std::chrono::steady_clock;

/// The frame rate the window aims at: it sleeps the rest of each 1/60 s, leaving the cores to
/// the physics.
constexpr double kFramePeriod = 1.0 / 60.0;
/// m of arrow per N of tool force (the liver's forces are 0.1-2 N).
constexpr double kArrowPerNewton = 0.08;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// The parameter editor's value of one parameter: the effective value, edited in place.
void edit_parameter(const ParameterDoc& doc, nlohmann::json& value) {
  const char* name = doc.name.c_str();
  if (value.is_boolean()) {
    bool flag = value.get<bool>();
    if (ImGui::Checkbox(name, &flag)) {
      value = flag;
    }
  } else if (value.is_number_integer()) {
    int number = value.get<int>();
    if (ImGui::InputInt(name, &number)) {
      value = number;
    }
  } else if (value.is_number()) {
    double number = value.get<double>();
    if (ImGui::InputDouble(name, &number, 0.0, 0.0, "%.6g")) {
      value = number;
    }
  } else if (value.is_string()) {
    char text[128] = {};
    const std::string current = value.get<std::string>();
    current.copy(text, sizeof(text) - 1);
    if (ImGui::InputText(name, text, sizeof(text))) {
      value = std::string(text);
    }
  } else {
    ImGui::TextDisabled("%s: %s", name, value.dump().c_str());
  }
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip("%s", doc.description.c_str());
  }
}

/// One viewport: its model, the parameters being edited, and what the panel last said.
struct Viewport {
  std::unique_ptr<LiveModel> model;
  nlohmann::json edits;  ///< the parameter editor's values
  std::string message;   ///< the last Apply's or model change's error
  LiveFrame frame;       ///< this window frame's copy
  // What this window frame draws of it, the storage kept from frame to frame.
  render::SurfaceFrame body;    ///< the surface
  render::SurfaceFrame extras;  ///< the tool, its force, the contacts
  render::SurfaceFrame tets;    ///< the tet view's faces
  int inverted = 0;             ///< tets inverted in `frame`
};

class App {
 public:
  App(const scenes::Scene& scene, const harness::SceneMesh& mesh, const ViewOptions& options)
      : scene_(scene), mesh_(mesh), options_(options), surface_(mesh.body) {
    for (const std::string& name : options.models) {
      viewports_.emplace_back();
      viewports_.back().model = std::make_unique<LiveModel>(scene, mesh, name);
      viewports_.back().model->reset(options.drive);
    }
    drive_ = options.drive;
  }

  void run(GLFWwindow* window);

 private:
  void replay(double time);
  void handle_mouse_and_keys();
  void mouse_down(const Eigen::Vector2d& pixel);
  void mouse_move(const Eigen::Vector2d& pixel);
  void mouse_up();
  void key(char key);
  void send();
  void panel();
  void overlay(std::size_t index);
  void build(std::size_t index);
  void draw(std::size_t index);
  render::Camera camera() const;
  render::Viewport viewport(std::size_t index) const;
  void write_report(double seconds) const;

  const scenes::Scene& scene_;
  const harness::SceneMesh& mesh_;
  const ViewOptions& options_;
  render::BodySurface surface_;
  std::unique_ptr<render::SurfaceRenderer> renderer_;
  std::vector<Viewport> viewports_;
  Drive drive_ = Drive::kHand;
  bool playing_ = true;
  bool wireframe_ = false;
  bool tets_ = false;
  bool contacts_ = true;
  bool force_ = true;

  // The hand.
  ToolCommand command_;
  double press_y_ = 0.0;           ///< window pixel where the press began
  double metres_per_pixel_ = 0.0;  ///< at the picked point's depth
  // The view: turned about z and up or down from the pictures' direction, moved back by zoom.
  double azimuth_ = 0.0;
  double elevation_ = 0.0;
  double zoom_ = 1.0;

  // The window, in framebuffer pixels (a HiDPI screen's framebuffer is larger than the window).
  int framebuffer_width_ = 0;
  int framebuffer_height_ = 0;
  int window_width_ = 0;
  int window_height_ = 0;
  std::size_t next_event_ = 0;
  bool quit_ = false;
  std::vector<std::filesystem::path> screenshots_;  ///< taken at the end of this frame
  std::deque<Clock::time_point> recent_frames_;     ///< the last second's
  double frames_per_second_ = 0.0;
  /// What the panel showed at each whole second of the run (the frame rate over the second).
  std::vector<double> shown_rates_;
  double draw_ms_ = 0.0;
  long long frames_ = 0;
  /// The longest time a model was seen behind real time by more than 5% (s of wall time).
  std::vector<double> behind_seconds_;
};

render::Camera App::camera() const {
  const double aspect = static_cast<double>(viewport(0).width) / std::max(1, viewport(0).height);
  const Eigen::Vector3d base = harness::kPicturesDirection;
  const Eigen::AngleAxisd turn(azimuth_, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(base).normalized();
  const Eigen::AngleAxisd tilt(elevation_, turn * side);
  return harness::pictures_camera(mesh_, aspect, tilt * (turn * base), zoom_);
}

render::Viewport App::viewport(std::size_t index) const {
  const int count = static_cast<int>(viewports_.size());
  const int width = framebuffer_width_ / count;
  return {static_cast<int>(index) * width, 0, width, framebuffer_height_};
}

void App::send() {
  for (Viewport& view : viewports_) {
    view.model->command(command_);
  }
}

void App::mouse_down(const Eigen::Vector2d& pixel) {
  if (drive_ != Drive::kHand || window_width_ <= 0) {
    return;
  }
  // Window pixels to framebuffer pixels, then into the viewport under the mouse.
  const double scale = static_cast<double>(framebuffer_width_) / window_width_;
  const Eigen::Vector2d at = pixel * scale;
  const auto index = std::min(viewports_.size() - 1,
                              static_cast<std::size_t>(at.x() / std::max(1, viewport(0).width)));
  const render::Viewport port = viewport(index);
  const Eigen::Vector2d local(at.x() - port.x, at.y());
  const render::Camera view = camera();
  const std::optional<render::SurfaceHit> hit = surface_.pick(
      viewports_[index].frame.positions, view.ray_through(local, port.width, port.height));
  if (!hit) {
    return;
  }
  command_.pressing = true;
  command_.point = hit->point;
  command_.normal = hit->normal;
  command_.rest_point = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    command_.rest_point +=
        hit->weights[k]
        * mesh_.body.rest_positions().col(hit->vertices[static_cast<std::size_t>(k)]);
  }
  command_.depth = 0.0;
  command_.grasp = false;
  ++command_.press;
  press_y_ = pixel.y();
  // A pixel's size at the picked point's distance: dragging moves the tip with the mouse.
  metres_per_pixel_ =
      hit->distance * 2.0 * std::tan(0.5 * render::kFieldOfView) / std::max(1, port.height) * scale;
  send();
}

void App::mouse_move(const Eigen::Vector2d& pixel) {
  if (!command_.pressing) {
    return;
  }
  // Down the screen presses in; up pulls out (what a grasp needs).
  command_.depth = std::clamp((pixel.y() - press_y_) * metres_per_pixel_, -HandTool::kMaxDepth,
                              HandTool::kMaxDepth);
  send();
}

void App::mouse_up() {
  if (!command_.pressing) {
    return;
  }
  command_.pressing = false;
  command_.grasp = false;
  send();
}

void App::key(char key) {
  switch (key) {
    case 'g':
      if (command_.pressing) {
        command_.grasp = !command_.grasp;
        send();
      }
      break;
    case ' ':
      playing_ = !playing_;
      for (Viewport& view : viewports_) {
        view.model->play(playing_);
      }
      break;
    case 's':
      for (Viewport& view : viewports_) {
        view.model->step_once();
      }
      break;
    case 'r':
    case 'p':
    case 'h':
      drive_ = key == 'p' ? Drive::kScript : key == 'h' ? Drive::kHand : drive_;
      command_ = ToolCommand{};
      for (Viewport& view : viewports_) {
        view.model->command(command_);
        view.model->reset(drive_);
      }
      break;
    case 'w':
      wireframe_ = !wireframe_;
      break;
    case 't':
      tets_ = !tets_;
      break;
    default:
      break;
  }
}

void App::replay(double time) {
  while (next_event_ < options_.input.size() && options_.input[next_event_].time <= time) {
    const InputEvent& event = options_.input[next_event_++];
    switch (event.kind) {
      case InputEvent::Kind::kMouseDown:
        mouse_down(event.pixel);
        break;
      case InputEvent::Kind::kMouseMove:
        mouse_move(event.pixel);
        break;
      case InputEvent::Kind::kMouseUp:
        mouse_up();
        break;
      case InputEvent::Kind::kKey:
        key(event.key);
        break;
      case InputEvent::Kind::kScreenshot:
        screenshots_.push_back(event.file);
        break;
      case InputEvent::Kind::kQuit:
        quit_ = true;
        break;
    }
  }
}

void App::handle_mouse_and_keys() {
  const ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureMouse) {
    const Eigen::Vector2d mouse(io.MousePos.x, io.MousePos.y);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
      mouse_down(mouse);
    } else if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && command_.pressing) {
      mouse_move(mouse);
    }
    if (ImGui::IsMouseDown(ImGuiMouseButton_Right)) {
      azimuth_ -= 0.01 * io.MouseDelta.x;
      elevation_ = std::clamp(elevation_ + 0.01 * io.MouseDelta.y, -1.2, 1.2);
    }
    if (io.MouseWheel != 0.0F) {
      zoom_ = std::clamp(zoom_ * std::pow(0.9, io.MouseWheel), 0.2, 5.0);
    }
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    mouse_up();
  }
  if (!io.WantCaptureKeyboard) {
    for (const char letter : {'g', 's', 'r', 'p', 'h', 'w', 't'}) {
      if (ImGui::IsKeyPressed(GLFW_KEY_A + (letter - 'a'), false)) {
        key(letter);
      }
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) {
      key(' ');
    }
  }
}

void App::panel() {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85F);
  ImGui::Begin("softbench view");
  ImGui::Text("%s", scene_.name.c_str());
  ImGui::Text("%.0f frames/s, %.2f ms to draw a frame", frames_per_second_, draw_ms_);
  if (ImGui::Button(playing_ ? "Pause" : "Play")) {
    key(' ');
  }
  ImGui::SameLine();
  if (ImGui::Button("Step")) {
    key('s');
  }
  ImGui::SameLine();
  if (ImGui::Button("Reset")) {
    key('r');
  }
  int drive = drive_ == Drive::kHand ? 0 : 1;
  if (ImGui::RadioButton("hand", &drive, 0) && drive_ != Drive::kHand) {
    key('h');
  }
  ImGui::SameLine();
  if (ImGui::RadioButton("the scene's script", &drive, 1) && drive_ != Drive::kScript) {
    key('p');
  }
  ImGui::Checkbox("wireframe", &wireframe_);
  ImGui::SameLine();
  ImGui::Checkbox("tets", &tets_);
  ImGui::SameLine();
  ImGui::Checkbox("contacts", &contacts_);
  ImGui::SameLine();
  ImGui::Checkbox("force", &force_);
  ImGui::PushTextWrapPos(0.0F);
  ImGui::TextDisabled(
      "drag on the body: press (down: deeper); G: grasp, then drag up: pull; "
      "right drag: turn; wheel: zoom; space: pause; S: step; R: reset");
  ImGui::PopTextWrapPos();
  const std::vector<std::string> names = builtin_models().names();
  for (std::size_t i = 0; i < viewports_.size(); ++i) {
    Viewport& view = viewports_[i];
    ImGui::PushID(static_cast<int>(i));
    const std::string title = "viewport " + std::to_string(i + 1) + ": " + view.model->model();
    if (ImGui::CollapsingHeader(title.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) {
      if (ImGui::BeginCombo("model", view.model->model().c_str())) {
        for (const std::string& name : names) {
          if (ImGui::Selectable(name.c_str(), name == view.model->model())
              && name != view.model->model()) {
            try {
              auto model = std::make_unique<LiveModel>(scene_, mesh_, name);
              model->command(command_);
              model->reset(drive_);
              model->play(playing_);
              view.model = std::move(model);
              view.edits = nlohmann::json();
              view.message.clear();
            } catch (const InputError& error) {
              view.message = error.what();
            }
          }
        }
        ImGui::EndCombo();
      }
      const ModelInfo& info = builtin_models().at(view.model->model());
      if (view.edits.is_null()) {
        view.edits = view.frame.parameters;
      }
      if (ImGui::TreeNode("parameters")) {
        for (const ParameterDoc& doc : info.parameters) {
          if (view.edits.contains(doc.name)) {
            edit_parameter(doc, view.edits[doc.name]);
          }
        }
        if (ImGui::Button("Apply (restarts)")) {
          view.message = view.model->set_parameters(view.edits);
        }
        ImGui::TreePop();
      }
      if (!view.message.empty()) {
        ImGui::TextColored(ImVec4(0.8F, 0.1F, 0.1F, 1.0F), "%s", view.message.c_str());
      }
    }
    ImGui::PopID();
  }
  ImGui::End();
}

void App::overlay(std::size_t index) {
  const Viewport& view = viewports_[index];
  const LiveFrame& frame = view.frame;
  const render::Viewport port = viewport(index);
  const double scale = static_cast<double>(window_width_) / std::max(1, framebuffer_width_);
  // At the viewport's bottom left, clear of the panel (top left) and of the body.
  ImGui::SetNextWindowPos(
      ImVec2(static_cast<float>(port.x * scale + 8.0), static_cast<float>(window_height_ - 8)),
      ImGuiCond_Always, ImVec2(0.0F, 1.0F));
  ImGui::SetNextWindowBgAlpha(0.6F);
  const std::string name = "##overlay" + std::to_string(index);
  ImGui::Begin(name.c_str(), nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize
                   | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  ImGui::Text("%s  (%s)", view.model->model().c_str(),
              frame.drive == Drive::kHand ? "hand" : "script");
  ImGui::Text("t = %.2f s, %.0f steps/s, %.2f ms a step", frame.time, frame.steps_per_second,
              frame.step_ms);
  if (!frame.failure.empty()) {
    ImGui::TextColored(ImVec4(0.8F, 0.1F, 0.1F, 1.0F), "%s", frame.failure.c_str());
  } else if (frame.ended) {
    ImGui::Text("the script has ended (R: again, H: the hand)");
  } else if (!frame.playing) {
    ImGui::Text("paused");
  } else if (frame.real_time < 0.95) {
    ImGui::TextColored(ImVec4(0.8F, 0.3F, 0.0F, 1.0F),
                       "cannot keep real time: %.2fx (a step takes %.1f ms of %.1f)",
                       frame.real_time, frame.step_ms, 1000.0 * scene_.dt);
  } else {
    ImGui::Text("real time");
  }
  ImGui::Text("tool force %.3f N, %zu vertices in contact%s", frame.tool_force.norm(),
              frame.contacts.size(), frame.grasping ? ", grasping" : "");
  if (view.inverted > 0) {
    ImGui::TextColored(ImVec4(0.7F, 0.55F, 0.0F, 1.0F), "%d tets inverted (yellow)", view.inverted);
  }
  ImGui::End();
}

void App::build(std::size_t index) {
  Viewport& view = viewports_[index];
  const LiveFrame& frame = view.frame;
  view.body.clear();
  view.extras.clear();
  view.tets.clear();
  view.inverted = surface_.append(frame.positions, view.body);
  const double diagonal = mesh_.diagonal();
  if (frame.tool_visible && mesh_.instrument) {
    render::append_instrument(*mesh_.instrument, frame.tool_pose, view.extras);
    if (force_ && frame.tool_force.norm() > 1e-6) {
      const Eigen::Vector3d tip = frame.tool_pose.translation();
      const Eigen::Vector3d arrow = kArrowPerNewton * frame.tool_force;
      const double length = std::min(arrow.norm(), 0.5 * diagonal);
      render::append_arrow(tip, tip + length * arrow.normalized(), 0.012 * diagonal,
                           render::kForceColour, view.extras);
    }
  }
  if (contacts_) {
    for (const int vertex : frame.contacts) {
      render::append_marker(frame.positions.col(vertex), 0.008 * diagonal, render::kContactColour,
                            view.extras);
    }
  }
  if (tets_) {
    render::append_tet_faces(mesh_.body.tets(), frame.positions, render::kTissueColour, view.tets);
  }
}

void App::draw(std::size_t index) {
  const Viewport& view = viewports_[index];
  const render::Camera eye = camera();
  const render::Viewport port = viewport(index);
  // The body: its shaded surface, or (the tet view) every tet's edges, seen through.
  if (tets_) {
    renderer_->draw(view.extras, eye, port, render::DrawOptions{true, true, false});
    renderer_->draw(view.tets, eye, port, render::DrawOptions{false, false, true});
    return;
  }
  renderer_->draw(view.body, eye, port, render::DrawOptions{true, true, wireframe_});
  renderer_->draw(view.extras, eye, port, render::DrawOptions{false, true, false});
}

void App::run(GLFWwindow* window) {
  renderer_ = std::make_unique<render::SurfaceRenderer>();
  behind_seconds_.assign(viewports_.size(), 0.0);
  const Clock::time_point opened = Clock::now();
  Clock::time_point last = opened;
  while (!quit_ && glfwWindowShouldClose(window) == 0 && !harness::interrupt_requested()) {
    const Clock::time_point begin = Clock::now();
    glfwPollEvents();
    glfwGetFramebufferSize(window, &framebuffer_width_, &framebuffer_height_);
    glfwGetWindowSize(window, &window_width_, &window_height_);
    for (std::size_t i = 0; i < viewports_.size(); ++i) {
      viewports_[i].frame = viewports_[i].model->frame();
      build(i);
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    replay(seconds_between(opened, begin));
    handle_mouse_and_keys();
    panel();
    for (std::size_t i = 0; i < viewports_.size(); ++i) {
      overlay(i);
      const LiveFrame& frame = viewports_[i].frame;
      if (frame.playing && frame.failure.empty() && frame.real_time > 0.0
          && frame.real_time < 0.95) {
        behind_seconds_[i] += seconds_between(last, begin);
      }
    }
    last = begin;
    ImGui::Render();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, framebuffer_width_, framebuffer_height_);
    glClearColor(render::kBackground, render::kBackground, render::kBackground, 1.0F);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (std::size_t i = 0; i < viewports_.size(); ++i) {
      draw(i);
    }
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    for (const std::filesystem::path& file : screenshots_) {
      glReadBuffer(GL_BACK);
      render::write_png(file, render::read_framebuffer(framebuffer_width_, framebuffer_height_));
    }
    screenshots_.clear();
    glfwSwapBuffers(window);
    ++frames_;
    const Clock::time_point end = Clock::now();
    draw_ms_ = 1000.0 * seconds_between(begin, end);
    recent_frames_.push_back(end);
    while (seconds_between(recent_frames_.front(), end) > 1.0) {
      recent_frames_.pop_front();
    }
    frames_per_second_ =
        recent_frames_.size() < 2
            ? 0.0
            : (recent_frames_.size() - 1) / seconds_between(recent_frames_.front(), end);
    if (seconds_between(opened, end) >= static_cast<double>(shown_rates_.size() + 1)) {
      shown_rates_.push_back(frames_per_second_);
    }
    // Sleep out the rest of the frame: the cores are the physics'.
    const double rest = kFramePeriod - seconds_between(begin, Clock::now());
    if (rest > 0.0) {
      glfwWaitEventsTimeout(rest);
    }
  }
  if (!options_.report.empty()) {
    write_report(seconds_between(opened, Clock::now()));
  }
}

void App::write_report(double seconds) const {
  nlohmann::json report;
  report["scene"] = scene_.name;
  report["seconds"] = seconds;
  report["frames"] = frames_;
  // Over the whole run, the window's start-up included; and the rate the panel showed at each
  // whole second (over the second before it), its median and its lowest.
  report["frames_per_second"] = seconds > 0.0 ? static_cast<double>(frames_) / seconds : 0.0;
  std::vector<double> shown = shown_rates_;
  std::sort(shown.begin(), shown.end());
  report["frames_per_second_shown"] = shown_rates_;
  report["frames_per_second_shown_median"] = shown.empty() ? 0.0 : shown[shown.size() / 2];
  report["frames_per_second_shown_lowest"] = shown.empty() ? 0.0 : shown.front();
  report["window"] = {framebuffer_width_, framebuffer_height_};
  for (std::size_t i = 0; i < viewports_.size(); ++i) {
    const LiveFrame frame = viewports_[i].model->frame();
    report["viewports"].push_back({{"model", viewports_[i].model->model()},
                                   {"time", frame.time},
                                   {"steps", frame.steps},
                                   {"steps_per_second", frame.steps_per_second},
                                   {"real_time", frame.real_time},
                                   {"step_ms", frame.step_ms},
                                   {"seconds_behind_real_time", behind_seconds_[i]},
                                   {"failure", frame.failure},
                                   {"parameters", frame.parameters}});
  }
  write_file_atomically(options_.report, [&](std::ostream& out) { out << report.dump(2) << "\n"; });
}

/// The window, its GL context and Dear ImGui on it, from opening to closing.
class Window {
 public:
  Window(const std::string& title, int width, int height) {
    if (glfwInit() == GLFW_FALSE) {
      throw InputError(
          "softbench view: no display to open a window on (set DISPLAY, or run "
          "under xvfb-run)");
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (window_ == nullptr) {
      glfwTerminate();
      throw std::runtime_error("softbench view: no OpenGL 3.3 core window on this display");
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(0);  // paced by the loop, not the display
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
    ImGui::StyleColorsLight();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
  }
  ~Window() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
  GLFWwindow* get() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace

void run_viewer(const scenes::Scene& scene,
                const harness::SceneMesh& mesh,
                const ViewOptions& options) {
  if (options.models.empty() || options.models.size() > 2) {
    throw InputError("softbench view: one or two models, one viewport each");
  }
  const Window window("softbench view: " + scene.name, options.width, options.height);
  // The models' threads stop (App's destructor) before the window closes.
  App app(scene, mesh, options);
  app.run(window.get());
}

}  // namespace softbench::viewer

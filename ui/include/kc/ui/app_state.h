#pragma once
/// The one object the GUI reads and writes each frame (STYLE.md, Immediate-mode UI), in four parts:
/// the document (picture, session, draft cage, pose, undo history), how it is shown (view, show
/// options, heatmap), the interaction (tool, selection, brushes, dialogs, messages) and the jobs
/// (worker, timings). No globals.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kc/app/backend.h"
#include "kc/app/diagnostics.h"
#include "kc/app/field_sampler.h"
#include "kc/app/session.h"
#include "kc/core/rasterize.h"
#include "kc/core/warp_mesh.h"
#include "kc/ui/bound_snapshot.h"
#include "kc/ui/cached.h"
#include "kc/ui/file_dialog.h"
#include "kc/ui/tools/brush_tool.h"
#include "kc/ui/tools/cage_tool.h"
#include "kc/ui/tools/line_tool.h"
#include "kc/ui/tools/pose_tool.h"
#include "kc/ui/tools/rigidity_tool.h"
#include "kc/ui/undo.h"
#include "kc/ui/view.h"
#include "kc/ui/worker.h"

namespace kc::ui {

enum class Tool { Pose, Brush, Cage, Lines, Rigid };

struct BrushSettings {
  double radius = 30.0;     ///< Image pixels.
  double strength = 0.25;   ///< Change of the target weight per dab at the centre.
  bool subtract = false;    ///< Ctrl inverts while painting.
};

/// The rigidity brush (tools/rigidity_tool.h).
struct RigidBrushSettings {
  double radius = 25.0;     ///< Image pixels.
  double softness = 0.5;    ///< Share of the radius over which the brush fades out (0 hard edge, 1 all soft).
  double strength = 1.0;    ///< The ρ the brush's centre paints (1: as rigid as the moved points allow).
  bool erase = false;       ///< Erase mode (Ctrl inverts while painting).
};

struct HeatmapSettings {
  bool show = true;         ///< In the brush tool.
  bool showInPose = false;  ///< In the pose tool (off: the picture stays clean while posing).
  bool log = false;
  float opacity = 0.55f;
  double logFloor = 1e-4;
};

struct ViewOptions {
  bool lines = true;  ///< Structure lines over the picture (always shown in the line tool).
  bool rigid = true;  ///< Rigid regions (tint and polygon outlines; always shown in the rigidity tool).
  bool cage = true, samples = false, mesh = false, foldovers = true, restCage = false;
  /// The sample plot coloured by the local spacing of a graded sampling (with a legend); off, or a
  /// uniform sampling: coloured by kind.
  bool sampleSpacing = true;
};

/// Measured times (milliseconds unless noted) shown in the diagnostics panel.
struct Timings {
  double bindSeconds = 0.0;
  double reoptimizeMs = 0.0;     ///< Last re-optimization (optimizer + field solve).
  Index reoptimizeSamples = 0;
  double meshWeightsMs = 0.0;    ///< Weights at the display mesh's vertices.
  double meshSetWeightsMs = 0.0;  ///< The display mesh taking the new weights (compact rows, pinned exterior data).
  /// Stroke release (or method switch) → the end of the frame that shows the new weights (its
  /// deform, uploads, draw and buffer swap included).
  double releaseToPictureMs = 0.0;
  double releaseJobMs = 0.0;      ///< Of releaseToPictureMs: release → the job's result (reoptimizeMs + mesh weights).
  double releaseFrameMs = 0.0;    ///< Of releaseToPictureMs: the frame that took the result (deform, uploads, draw).
  double frameMs = 0.0, deformMs = 0.0, uploadMs = 0.0;
  std::size_t uploadBytes = 0;    ///< Vertex data sent to the GPU by the last frame.
  double openMs = 0.0;            ///< Reading the last picture opened from a file.
  double textureMs = 0.0;         ///< Display texture of the last picture: resampling + upload.
  double detailMs = 0.0;          ///< Last detail texture: crop + resampling + upload.
};

/// What the renderer draws the picture from (renderer.h): the display texture's size and the
/// detail texture in use (0×0: none).
struct DisplayTextures {
  int width = 0, height = 0;
  int detailWidth = 0, detailHeight = 0;
  double detailScale = 0.0;  ///< Detail texels per picture pixel.
};

/// What the canvas is doing with the mouse between press and release.
struct CanvasDrag {
  int button = -1;          ///< 0 left, 1 right, 2 middle; −1 = no drag.
  bool panning = false;     ///< Middle-drag or space+left-drag.
  Vec2 lastScreen = Vec2::Zero();
};

/// One mouse event as the window system delivered it (the window's GLFW callbacks): ImGui 1.86
/// samples the mouse once per frame, so two clicks within one slow frame would become one, at the
/// later position. The canvas replays these in order (handleCanvasInput).
struct PointerInput {
  enum class Kind { Press, Release, Move };
  Kind kind = Kind::Move;
  int button = 0;            ///< 0 left, 1 right, 2 middle (Press, Release).
  Vec2 screen = Vec2::Zero();  ///< Where it happened (screen pixels, the window's coordinates).
  bool shift = false, ctrl = false;  ///< Modifiers held (Press, Release; a Move takes the frame's).
};

/// Which deform the display mesh shows: of which pose and mesh, and whether it was a DeformPass::Live
/// one (during a pose drag: once the drag ends, the pose is deformed again with the full repair, as
/// the export does).
struct DeformKey {
  Version pose, mesh;
  bool live = false;
  bool operator==(const DeformKey&) const = default;
};

struct AppState;

struct Message {
  std::string text;
  bool error = false;
  bool offersUndo = false;  ///< The status bar shows an Undo button beside it (a fold's fix).
};

/// Something that would discard unsaved work, waiting for the user's answer (Open, New, Quit), or
/// an action with a consequence the user should know of first (`question`: Bind again).
struct PendingAction {
  std::string what;                          ///< Names the action on the prompt's buttons: "Open", "New", "Quit".
  std::function<void(AppState&)> run;
  /// Empty: the unsaved-changes prompt (Save and …, … without saving, Cancel). Else this question,
  /// with the buttons `what` and Cancel.
  std::string question = {};
};

/// The document: the picture, the bound session and what is shown of it, the draft cage, the lines,
/// the pose, the display warp mesh, the outside mode, the undo history, the paths and the unsaved
/// state (autosave).
struct Document {
  Image source;                            ///< The picture (RGBA8), full resolution (the export's; drawn from textures sized for the screen).
  std::string imagePath;
  /// `source` is the picture turned as its Exif orientation says (app::Session::imageUpright);
  /// false for the picture of a session written before kcwarp read the orientation.
  bool imageUpright = true;
  Version sourceVersion;  ///< Of `source` (the display texture's upload).
  /// The bound session; null when nothing is bound or while a worker job holds it.
  std::shared_ptr<app::Session> session;
  /// What is shown of the bound session (also while a job holds it); null when nothing is bound.
  /// Made by makeBoundSnapshot when a bind, an opened session or a job's result is installed.
  std::shared_ptr<const BoundSnapshot> bound;
  /// W is what the optimizer gives for (W0, method) in every row (after a bind or a whole
  /// re-optimization; not for a session file, which may come from another version).
  bool weightsReproducible = false;
  std::string rigidityDetails;             ///< The last rigidity solve in the solver's words (diagnostics).
  app::BindParams bindParams;              ///< Bind panel values (next bind).
  /// Bind chooses the spacing from a sample budget (app::automaticSpacing, as kcwarp-cli does
  /// without --spacing): 6 px up to about a megapixel, wider beyond, so a big picture binds in
  /// seconds. Off: bindParams.spacing as set by the slider (or --spacing).
  bool autoSpacing = true;
  /// The automatic spacing the Bind panel shows and what it was computed from (cage, picture size,
  /// the parameters the estimate reads), so that the narrowest-place search over the cage runs
  /// when one of them changes, not every frame (autoSpacingShown()).
  struct ShownSpacing {
    Points cage;
    int width = 0, height = 0;
    app::BindParams params;
    app::Structure lines;
    /// What the next bind uses (spacingPlan()): the spacing h away from narrow places, the
    /// smallest h of its sizing field (== spacing for a uniform bind) and the estimated number of
    /// samples (kc) or mesh vertices (LBC); the screened targets' locality length in pixels
    /// (app::locality with those parameters; 0 when the targets are not screened).
    double spacing = 0.0, minSpacing = 0.0, points = 0.0, locality = 0.0;
    bool closed = false, cageValid = false;  ///< the draft cage's (an open cage binds as sticks)
  } shownSpacing;
  Cage cage;  ///< Draft cage of the cage tool (== bound->cage after a bind).
  bool cageValid = false;
  std::string cageStatus;                  ///< Why the draft cage cannot be bound (empty when valid).
  /// Structure lines kept straight / parallel (thesis 5.3): the next bind's lines; after a bind or
  /// open, the bound session's. Edited by the line tool (editLines), which re-binds.
  app::Structure lines;
  /// While a rigidity job runs, the ρ it is solving for (#S), shown instead of the session's
  /// (boundRigidity()).
  std::optional<std::vector<double>> solvingRigidity;
  Version rigidityVersion;                 ///< Of the ρ shown (boundRigidity() or the stroke being painted).
  Pose pose;                               ///< Current pose, one handle per bound control point.
  Version poseVersion;
  /// What happens outside the cage, in the view and the export (saved in the session as "outside").
  OutsideMode outside = OutsideMode::Pinned;
  WarpMesh mesh;                           ///< Display warp mesh (weights at its vertices).
  /// Where the display mesh's weights come from: the field sampler at its vertices and the dense
  /// vertex weights, so a paint stroke re-evaluates only the controls whose weights changed.
  struct MeshSource {
    app::FieldSampler sampler;
    Weights W;
  };
  std::shared_ptr<MeshSource> meshSource;
  Version meshVersion;  ///< Of `mesh` and its weights.
  /// The display mesh's deform (DeformKey); the renderer uploads the positions once per key.
  CachedEffect<DeformKey> deformed;
  DeformReport deformReport;
  /// Folded triangles of the last full deform the status bar was told of (updateDeformation): a
  /// deform that folds more says so in plain words with its fix; one that unfolds says that too.
  Index foldsTold = 0;
  std::optional<app::Diagnostics> diagnostics;
  std::string sessionPath, exportPath, recoveryPath;
  bool unsaved = false;
  double lastAutosave = 0.0;               ///< Seconds (glfw/steady clock) of the last autosave.
  UndoStack undo;
};

/// How the document is shown: the view, the show options, the heatmap, the display textures and the
/// caches drawn from.
struct ViewState {
  View view;
  bool fitPending = true;                  ///< Fit the view at the next frame (new image).
  bool showOriginal = false;               ///< Before/after: the original picture while O is held.
  bool hideCage = false;                   ///< The warp without the cage, its handles and lines while H is held (pose, brush, rigid tools).
  HeatmapSettings heat;
  ViewOptions show;
  /// ρ at the display mesh's vertices for the tint (rigidity_overlay.cpp), of (meshVersion,
  /// rigidityVersion).
  Cached<std::vector<float>, std::pair<Version, Version>> rigidTint;
  DisplayTextures display;  ///< Set by the renderer.
  /// Set by a frame that left work for the next one (the renderer defers the detail texture while
  /// the view moves): the window draws one more frame before it sleeps.
  bool frameWanted = false;
  /// Heatmap colour bar range of the shown weights (set by the renderer's heat pass).
  double heatLow = 0.0, heatHigh = 1.0;
};

/// What the person is doing: the tool and its state, the selection, the brushes, the pointer and key
/// queues, dialogs, prompts and messages.
struct Interaction {
  Tool tool = Tool::Pose;
  std::vector<Index> selection;            ///< Selected control points (pose tool).
  std::vector<int> lineSelection;          ///< Selected structure lines (line tool), indices into `lines`.
  std::string lineGroupName = "parallel 1";  ///< The line tool's name for the next parallel group.
  /// Pivot of a multi-selection's rotation where the user dragged it (posed image pixels);
  /// empty = the selection's centre. Forgotten when the selection changes.
  std::optional<Vec2> pivot;
  Index activeControl = -1;                ///< Control whose weights are painted and shown.
  BrushSettings brush;
  RigidBrushSettings rigidBrush;
  PoseTool poseTool;
  BrushTool brushTool;
  CageTool cageTool;
  LineTool lineTool;
  RigidityTool rigidTool;
  std::vector<Message> messages;
  bool helpOpen = false;                   ///< Help > How to / shortcuts window shown.
  bool quitRequested = false;              ///< Close asked while unsaved: confirm dialog open.
  bool quitConfirmed = false;              ///< The user agreed to close.
  CanvasDrag canvasDrag;
  bool canvasHovered = false;
  Vec2 mouseImage = Vec2::Zero();          ///< Mouse position in image pixels (status bar, brush ring).
  PathPurpose pathDialog = PathPurpose::None;
  std::string pathDialogText;
  bool pathDialogFocused = false;          ///< The dialog's path field has the keyboard (typing goes there).
  /// The in-app file dialog asks before saving over this file, which exists (empty: not asking).
  std::string replacePath;
  bool nativeDialogs = false;              ///< Use zenity/kdialog when installed (the window sets it).
  std::shared_ptr<NativeDialog> nativeDialog;  ///< A native dialog that is open.
  std::optional<PendingAction> unsavedPrompt;  ///< The unsaved-changes prompt is open for this action.
  std::function<void(AppState&)> afterSave;    ///< Runs after the next successful save (prompt's "Save and ...").
  std::vector<std::string> droppedPaths;   ///< Files dropped onto the window, handled next frame.
  /// Keys pressed since the last frame (GLFW key, modifier bits), as the window gives them to ImGui,
  /// for handleShortcuts: the window holds an editing key (Return, Escape, arrows, Ctrl+…) down for
  /// a frame at least, but lets a key that types a character go down and up between two frames (a
  /// quick B or C while a big picture draws at a few frames per second), which ImGui never sees.
  std::vector<std::pair<int, int>> tappedKeys;
  /// Ctrl shortcuts tapped in a frame where ImGui reported a text field as taking the keyboard,
  /// tried once more in the next frame: ImGui reports a field that closed (a dialog's path field)
  /// as taking text for one frame after, and a shortcut tapped then belongs to the window.
  std::vector<std::pair<int, int>> heldTaps;
  /// Mouse presses, releases and moves since the last frame, in order (PointerInput). Filled only
  /// when `pointerQueued` (the window's callbacks); otherwise the canvas reads ImGui's mouse state.
  std::vector<PointerInput> pointerInputs;
  bool pointerQueued = false;
  std::optional<Vec2> pointerAt;           ///< The last position the window's callbacks saw (a press's position).
  std::vector<std::string> recentFiles;    ///< Newest first (File > Open recent).
  std::string recentFilesPath;             ///< Where the list is kept; empty = not kept (tests).
  /// Screen centres of named widgets from the last frame (UI automation: the e2e test clicks them).
  std::map<std::string, Vec2> widgets;
};

/// Background work: the worker, commands deferred until it is free, and the measured times.
struct Jobs {
  Worker worker;
  Timings timings;
  /// Seconds (nowSeconds) at the stroke release whose picture is not shown yet, 0 when none: the
  /// job's result sets it, the window turns it into timings.releaseToPictureMs after the frame.
  double releaseStart = 0.0;
  std::function<void()> wakeup;            ///< Wakes the window's event loop from another thread.
  /// Commands asked for while a job held the session (Save, Export): run when the worker is free.
  std::vector<std::function<void(AppState&)>> deferred;
  int exportCount = 0;  ///< Successful exports in this run (automation).
};

/// The four parts as one object: a function that needs one part takes that part (a Document&, …),
/// and an AppState is each of them.
struct AppState : Document, ViewState, Interaction, Jobs {};

/// Seconds on a monotonic clock (for timings and autosave).
double nowSeconds();

}  // namespace kc::ui

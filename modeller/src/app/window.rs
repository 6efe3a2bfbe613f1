//! The winit window: owns the surface, the GPU and the egui integration, feeds input to the
//! [`Modeller`] and draws its scene and, through the [`Shell`], its panels.
//!
//! Each frame: egui runs the panels (which leave a rectangle for the 3D view), the modeller
//! brings its tessellation up to date and builds lines and spheres, the renderer draws the scene
//! into that rectangle (multisampled, through an sRGB view of the swapchain texture), and egui
//! draws on top. Pointer input reaches the modeller only when egui did not consume it — except
//! the moves and the release of a gesture the viewport started, so a drag never sticks.
//!
//! Whether a press is egui's is decided at the press's own position ([`over_ui`]), not only by
//! egui's `wants_pointer_input`: that answer is from the last frame, when the pointer may still
//! have been over the surface — a move onto a toolbar button and a click within one frame
//! would otherwise reach both the button and the sculpting tool.
//!
//! ## Slow frames
//!
//! Input is never read once per frame only. The modeller gets every winit pointer event as it
//! arrives. egui gets the events queued since the last frame, split into passes
//! ([`input_passes`]): one pointer press or release a pass, each pass timed when its last
//! event arrived, and the text typed after a click in a pass of its own. So at 4 frames per
//! second (software rendering) two clicks delivered in one frame are still a double click
//! (egui times clicks by the pass), and letters typed right after the click that focuses a text
//! field reach the field. Only the last pass of a frame is drawn.
//!
//! **Timing error.** An event is timed when winit delivers it, not when the X server saw it
//! (winit does not pass the server's event times on). While a frame draws, the event loop reads
//! nothing: an event that came then is delivered after the frame, late by up to the frame's
//! length, so two clicks 80 ms apart that straddle a 250 ms frame are delivered a frame apart.
//! The lateness is bounded, though. winit's loop runs in iterations: `new_events`, every
//! pending event (the queue is read until empty), the redraw, `about_to_wait`, then a wait that
//! ends at once when anything is pending. An event delivered in iteration `j` therefore came
//! after iteration `j − 1` had read the queue empty, which was after that iteration began at
//! `N_{j−1}`; and if the loop waited idle before `j`, the event itself ended the wait (an event
//! that came earlier would have left nothing to wait for). Either way it came no earlier than
//!
//! ```text
//! lo_j = N_j − B_{j−1},   B_{j−1} = the busy time of iteration j − 1 (new_events to about_to_wait)
//! ```
//!
//! (the idle wait is not counted; the few microseconds the system takes to wake the loop are
//! neglected). Each queued event keeps its `lo`. A pass timed `T` whose button event came no
//! earlier than `lo` is run with egui's click limits widened by its slack `s = T − lo`:
//! `max_double_click_delay = 0.3 + s` and `max_click_duration = 0.8 + s`. egui then counts the
//! second click of a pair as a double click when `T₂ − T₁ < 0.3 + T₂ − lo₂`, that is when
//! `lo₂ − T₁ < 0.3`. Since the first click came at `a₁ ≤ T₁` and the second at `a₂ ≥ lo₂`, every
//! pair truly less than 0.3 s apart (`a₂ − a₁ < 0.3`) counts, whatever the frames did (and a
//! press and its release a frame apart stay a click). The price: a pair up to `0.3 + s₁ + s₂`
//! apart may count as well — under Xvfb at `NENDO_FRAME_DELAY_MS=250` on a loaded machine
//! (frames of ≈ 0.45 s), clicks 0.6 s apart did; when frames are fast, `s` is a few
//! milliseconds and egui's limit is as it was. Widening by the time between two frames' input
//! stamps would bound the error too, but it counts the idle wait between frames: after a pause,
//! clicks seconds apart would count.
//!
//! Test aid: `NENDO_FRAME_DELAY_MS=250` makes every frame sleep that long after presenting
//! (`.ci/checks/window-live.sh` uses it to check the above at 4 frames per second).

use super::apply_textures;
use crate::editor::live::{DeviceWaker, LATCH_WAIT};
use anyhow::{Context as _, anyhow};
use glam::Vec2;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use super::shell::Shell;
use crate::editor::{Modeller, input::Button, input::PointerInput};
use crate::render::{FrameTargets, GpuContext, LineBatch, Renderer, SphereInstance};

/// Samples per pixel of the 3D view on a GPU. On a software adapter (Mesa's lavapipe or
/// llvmpipe) multisampling costs about three times the frame (`nendo bench render`), so the
/// view is drawn with one sample there.
const SAMPLES: u32 = 4;

/// Samples per pixel for an adapter.
fn samples_for(adapter: &wgpu::Adapter) -> u32 {
    if adapter.get_info().device_type == wgpu::DeviceType::Cpu {
        1
    } else {
        SAMPLES
    }
}

/// Everything that needs the window to exist.
struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    gpu: GpuContext,
    config: wgpu::SurfaceConfiguration,
    /// The sRGB view format the scene is drawn through (the surface's own format is what egui
    /// expects).
    scene_format: wgpu::TextureFormat,
    renderer: Renderer,
    targets: FrameTargets,
    /// Samples per pixel of the 3D view.
    samples: u32,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    lines: LineBatch,
    spheres: Vec<SphereInstance>,
    uploaded: super::surface_upload::SurfaceUpload,
    /// The 3D view in physical pixels: origin and size.
    viewport: (Vec2, Vec2),
    /// The cursor in window pixels.
    cursor: Vec2,
    /// The window title last set.
    title: String,
    /// When each event queued in egui's input arrived, and the earliest it can have
    /// happened (see the module docs).
    arrivals: Vec<Arrival>,
}

/// When a queued input event was delivered, and the earliest it can have happened: seconds
/// on [`WindowApp`]'s clock (see the module docs, "Timing error").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arrival {
    /// When winit delivered the event.
    pub at: f64,
    /// No earlier than this did the event happen (`lo` in the module docs).
    pub earliest: f64,
}

/// One egui pass of queued input: its events, the time it is run at, and its slack — how
/// much earlier than that time its pointer press or release may have happened (0 without
/// one).
#[derive(Debug, Clone, PartialEq)]
pub struct InputPass {
    /// The events.
    pub events: Vec<egui::Event>,
    /// The pass's time, seconds.
    pub time: f64,
    /// `T − lo` of its button event (see the module docs).
    pub slack: f64,
}

impl InputPass {
    /// egui's input options for this pass: `base`'s click limits widened by the slack.
    #[must_use]
    pub fn input_options(&self, base: egui::InputOptions) -> egui::InputOptions {
        egui::InputOptions {
            max_double_click_delay: base.max_double_click_delay + self.slack,
            max_click_duration: base.max_click_duration + self.slack,
            ..base
        }
    }
}

/// The window application.
pub struct WindowApp {
    modeller: Modeller,
    shell: Shell,
    gfx: Option<Gfx>,
    egui_ctx: egui::Context,
    error: Option<anyhow::Error>,
    next_redraw: Option<Instant>,
    /// The clock egui's input is timed on.
    clock: Instant,
    /// `NENDO_FRAME_DELAY_MS`: a sleep after each frame (a test aid).
    frame_delay: Option<Duration>,
    /// egui's input options as made (the click limits each pass widens).
    base_input: egui::InputOptions,
    /// When the event loop's current iteration began (`N_j`), on `clock`.
    iteration_start: f64,
    /// How long the last finished iteration was busy (`B_{j−1}`), seconds.
    last_busy: f64,
    /// The earliest an event delivered in this iteration can have happened (`lo_j`).
    earliest: f64,
}

/// Whether the window position `cursor` (physical pixels) is over egui's UI: over a window or
/// other area above the background, or outside the 3D view's rectangle `view` (origin and
/// size, physical pixels: the panels). Decided from the position itself and the areas of the
/// last frame, so it is right for a pointer that moved since that frame.
#[must_use]
pub fn over_ui(ctx: &egui::Context, cursor: Vec2, view: (Vec2, Vec2)) -> bool {
    let (origin, size) = view;
    let inside = cursor.x >= origin.x
        && cursor.y >= origin.y
        && cursor.x < origin.x + size.x
        && cursor.y < origin.y + size.y;
    let ppp = ctx.pixels_per_point().max(1e-3);
    let pos = egui::pos2(cursor.x / ppp, cursor.y / ppp);
    let above = ctx
        .layer_id_at(pos)
        .is_some_and(|layer| layer.order != egui::Order::Background);
    above || !inside
}

/// The environment variable that slows every frame down (a test aid, see the module docs).
pub const FRAME_DELAY_ENV: &str = "NENDO_FRAME_DELAY_MS";

/// Splits the events queued since the last frame (`events`, each with its [`Arrival`]) into
/// egui passes: a pass ends before a second pointer press or release, and before a key or
/// text event that follows a press or release (the click may move the keyboard focus, which
/// takes a pass). Each pass is timed by its last event, the last pass by `now`; its slack is
/// its time less the earliest its button event can have happened.
#[must_use]
pub fn input_passes(events: Vec<egui::Event>, arrivals: &[Arrival], now: f64) -> Vec<InputPass> {
    let mut passes = Vec::new();
    let mut current: Vec<egui::Event> = Vec::new();
    let mut time = now;
    // The earliest the current pass's button event can have happened.
    let mut button: Option<f64> = None;
    let slack = |time: f64, button: Option<f64>| button.map_or(0.0, |lo| (time - lo).max(0.0));
    for (k, event) in events.into_iter().enumerate() {
        let arrival = arrivals.get(k).copied().unwrap_or(Arrival {
            at: now,
            earliest: now,
        });
        let is_button = matches!(event, egui::Event::PointerButton { .. });
        let is_typing = matches!(
            event,
            egui::Event::Key { .. } | egui::Event::Text(_) | egui::Event::Paste(_)
        );
        if button.is_some() && (is_button || is_typing) {
            passes.push(InputPass {
                events: std::mem::take(&mut current),
                time,
                slack: slack(time, button),
            });
            button = None;
        }
        if is_button {
            button = Some(arrival.earliest);
        }
        time = arrival.at;
        current.push(event);
    }
    passes.push(InputPass {
        events: current,
        time: now,
        slack: slack(now, button),
    });
    passes
}

impl WindowApp {
    /// A window for `modeller`.
    #[must_use]
    pub fn new(modeller: Modeller) -> Self {
        let egui_ctx = egui::Context::default();
        let base_input = egui_ctx.options(|o| o.input_options);
        Self {
            modeller,
            shell: Shell::default(),
            gfx: None,
            egui_ctx,
            error: None,
            next_redraw: None,
            clock: Instant::now(),
            frame_delay: std::env::var(FRAME_DELAY_ENV)
                .ok()
                .and_then(|v| v.trim().parse::<u64>().ok())
                .filter(|ms| *ms > 0)
                .map(Duration::from_millis),
            base_input,
            iteration_start: 0.0,
            last_busy: 0.0,
            earliest: 0.0,
        }
    }

    /// Opens the window and runs until it closes.
    ///
    /// # Errors
    /// When no window or GPU can be had, or the event loop fails.
    pub fn run(mut self) -> anyhow::Result<()> {
        let event_loop = EventLoop::new().context("cannot open a window (is DISPLAY set?)")?;
        event_loop.set_control_flow(ControlFlow::Wait);
        event_loop
            .run_app(&mut self)
            .context("the window's event loop failed")?;
        match self.error {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn create_gfx(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<Gfx> {
        let attributes = Window::default_attributes()
            .with_title(self.modeller.title())
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 800.0));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create the window")?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(Arc::clone(&window))
            .context("cannot create a drawing surface")?;
        let gpu = GpuContext::with_instance(instance, Some(&surface))?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| anyhow!("the GPU adapter cannot draw into this window"))?;
        let caps = surface.get_capabilities(&gpu.adapter);
        config.format =
            egui_wgpu::preferred_framebuffer_format(&caps.formats).unwrap_or(config.format);
        let scene_format = config.format.add_srgb_suffix();
        if scene_format != config.format {
            config.view_formats = vec![scene_format];
        }
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(&gpu.device, &config);

        let samples = samples_for(&gpu.adapter);
        let renderer = Renderer::new(&gpu.device, scene_format, samples);
        let targets = FrameTargets::new(
            &gpu.device,
            scene_format,
            [config.width, config.height],
            samples,
        );
        let egui_state = egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            config.format,
            egui_wgpu::RendererOptions::default(),
        );
        eprintln!(
            "nendo: drawing with {}, {samples} sample(s) per pixel",
            gpu.describe()
        );
        Ok(Gfx {
            window,
            surface,
            gpu,
            config,
            scene_format,
            renderer,
            targets,
            samples,
            egui_state,
            egui_renderer,
            lines: LineBatch::new(),
            spheres: Vec::new(),
            uploaded: Default::default(),
            viewport: (Vec2::ZERO, Vec2::ONE),
            cursor: Vec2::ZERO,
            title: String::new(),
            arrivals: Vec::new(),
        })
    }

    fn resize(gfx: &mut Gfx, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        gfx.config.width = width;
        gfx.config.height = height;
        gfx.surface.configure(&gfx.gpu.device, &gfx.config);
        gfx.targets = FrameTargets::new(
            &gfx.gpu.device,
            gfx.scene_format,
            [width, height],
            gfx.samples,
        );
    }

    /// Runs one frame: UI, scene, drawing. Returns how long egui wants to wait before the next.
    fn redraw(&mut self) -> Option<Duration> {
        let gfx = self.gfx.as_mut()?;
        let start = Instant::now();
        self.modeller.tick(start);

        let mut raw = gfx.egui_state.take_egui_input(&gfx.window);
        let now_s = self.clock.elapsed().as_secs_f64();
        let arrivals = std::mem::take(&mut gfx.arrivals);
        let mut passes = input_passes(std::mem::take(&mut raw.events), &arrivals, now_s);
        let mut view_rect = egui::Rect::NOTHING;
        let (modeller, shell) = (&mut self.modeller, &mut self.shell);
        let base = self.base_input;
        let last = passes.pop().unwrap_or(InputPass {
            events: Vec::new(),
            time: now_s,
            slack: 0.0,
        });
        for pass in passes {
            // An earlier pass: its effects count, its drawing does not.
            self.egui_ctx
                .options_mut(|o| o.input_options = pass.input_options(base));
            let input = egui::RawInput {
                events: pass.events,
                time: Some(pass.time),
                hovered_files: Vec::new(),
                dropped_files: Vec::new(),
                ..raw.clone()
            };
            let out = self.egui_ctx.run_ui(input, |ui| {
                let _ = shell.ui(ui, modeller);
            });
            gfx.egui_state
                .handle_platform_output(&gfx.window, out.platform_output);
            apply_textures(
                &mut gfx.egui_renderer,
                &gfx.gpu.device,
                &gfx.gpu.queue,
                &out.textures_delta,
            );
        }
        self.egui_ctx
            .options_mut(|o| o.input_options = last.input_options(base));
        raw.events = last.events;
        raw.time = Some(last.time);
        let full = self
            .egui_ctx
            .run_ui(raw, |ui| view_rect = shell.ui(ui, modeller));
        gfx.egui_state
            .handle_platform_output(&gfx.window, full.platform_output);
        let ppp = full.pixels_per_point;
        let (width, height) = (gfx.config.width as f32, gfx.config.height as f32);
        let min = Vec2::new(view_rect.min.x * ppp, view_rect.min.y * ppp)
            .clamp(Vec2::ZERO, Vec2::new(width, height));
        let max = Vec2::new(view_rect.max.x * ppp, view_rect.max.y * ppp)
            .clamp(min, Vec2::new(width, height));
        let size = (max - min).max(Vec2::ONE);
        gfx.viewport = (min, size);
        self.modeller.set_viewport(size);
        // Acquire (the wait for the previous frame), then latch the input (`live::latency`).
        let (device, queue) = (&gfx.gpu.device, &gfx.gpu.queue);
        let frame = match gfx.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                gfx.surface.configure(device, &gfx.config);
                apply_textures(&mut gfx.egui_renderer, device, queue, &full.textures_delta);
                return Some(Duration::ZERO);
            }
            _ => {
                apply_textures(&mut gfx.egui_renderer, device, queue, &full.textures_delta);
                return Some(Duration::from_millis(16));
            }
        };
        self.modeller.latch_devices(LATCH_WAIT);
        self.modeller.refresh_for_frame();
        let title = self.modeller.title();
        if title != gfx.title {
            gfx.window.set_title(&title);
            gfx.title = title;
        }

        gfx.uploaded
            .update(&mut gfx.renderer, device, queue, &self.modeller);
        let style = self.modeller.scene(&mut gfx.lines, &mut gfx.spheres);
        gfx.renderer.set_lines(device, queue, &gfx.lines);
        gfx.renderer.set_spheres(device, queue, &gfx.spheres);
        let view = self.modeller.camera().view(size.x / size.y);
        gfx.renderer
            .set_analysis(queue, &self.modeller.panel().analysis, &view);
        gfx.renderer.prepare(queue, &view, &style, size.to_array());

        let scene_view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(gfx.scene_format),
            ..Default::default()
        });
        let ui_view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("nendo frame"),
        });
        {
            let mut pass = gfx.targets.begin_pass(&mut encoder, &scene_view);
            pass.set_viewport(min.x, min.y, size.x, size.y, 0.0, 1.0);
            gfx.renderer.draw(&mut pass);
        }

        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [gfx.config.width, gfx.config.height],
            pixels_per_point: ppp,
        };
        let primitives = self.egui_ctx.tessellate(full.shapes, ppp);
        for (id, deltas) in &full.textures_delta.set {
            for delta in deltas {
                gfx.egui_renderer.update_texture(device, queue, *id, delta);
            }
        }
        let extra =
            gfx.egui_renderer
                .update_buffers(device, queue, &mut encoder, &primitives, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("nendo ui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &ui_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            gfx.egui_renderer
                .render(&mut pass.forget_lifetime(), &primitives, &screen);
        }
        for id in &full.textures_delta.free {
            gfx.egui_renderer.free_texture(id);
        }
        queue.submit(extra.into_iter().chain([encoder.finish()]));
        // The device samples this frame shows: their latency to the submission, then to the
        // moment `present` returns (`editor::live` latency module docs say why that moment).
        self.modeller.frame_submitted(Instant::now());
        gfx.window.pre_present_notify();
        queue.present(frame);
        self.modeller.frame_presented(Instant::now());
        self.modeller.settle();

        self.modeller
            .record_frame_time(start.elapsed().as_secs_f64() * 1e3);
        if let Some(delay) = self.frame_delay {
            std::thread::sleep(delay);
        }

        let delay = full
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map_or(Duration::MAX, |v| v.repaint_delay);
        let now = Instant::now();
        let wake = self
            .modeller
            .wake_at(now)
            .map_or(Duration::MAX, |t| t.saturating_duration_since(now));
        let delay = delay.min(wake);
        Some(if self.modeller.animating() {
            delay.min(Duration::from_millis(16))
        } else {
            delay
        })
    }

    fn pointer(&mut self, input: PointerInput) {
        self.modeller.pointer(input);
        if let Some(gfx) = &self.gfx {
            gfx.window.request_redraw();
        }
    }
}

impl ApplicationHandler for WindowApp {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_gfx(event_loop) {
            Ok(gfx) => {
                gfx.window.request_redraw();
                // Device samples ask for a frame as they arrive (`editor::live`).
                let window = Arc::downgrade(&gfx.window);
                let wake = move || {
                    window
                        .upgrade()
                        .into_iter()
                        .for_each(|w| w.request_redraw())
                };
                self.modeller.set_device_waker(DeviceWaker(Arc::new(wake)));
                self.gfx = Some(gfx);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else { return };
        // Keys read by position (numpad 5: egui would take it for the main 5) never reach egui,
        // unless a text field has the keyboard.
        if let WindowEvent::KeyboardInput { event: key, .. } = &event
            && let winit::keyboard::PhysicalKey::Code(code) = key.physical_key
            && let Some(action) = super::keymap::physical_action(code)
            && !self.egui_ctx.egui_wants_keyboard_input()
        {
            if key.state == ElementState::Pressed && !key.repeat {
                self.modeller.apply(action.command());
                gfx.window.request_redraw();
            }
            return;
        }
        let queued = gfx.egui_state.egui_input().events.len();
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        let arrival = Arrival {
            at: self.clock.elapsed().as_secs_f64(),
            earliest: self.earliest,
        };
        let now_queued = gfx.egui_state.egui_input().events.len();
        gfx.arrivals.truncate(queued);
        gfx.arrivals.resize(queued, arrival);
        gfx.arrivals.resize(now_queued, arrival);
        // egui-winit asks for a repaint on every RedrawRequested; following it would redraw
        // forever. Redraws are scheduled from egui's repaint delay instead (see `redraw`).
        if response.repaint && !matches!(event, WindowEvent::RedrawRequested) {
            gfx.window.request_redraw();
        }
        let owns = self.modeller.owns_pointer();
        let (origin, _) = gfx.viewport;
        // The UI's own answer is from the last frame; the position decides as well.
        let ui_ctx = self.egui_ctx.clone();
        let viewport = gfx.viewport;
        let on_ui = |cursor: Vec2| over_ui(&ui_ctx, cursor, viewport);
        match event {
            WindowEvent::CloseRequested => {
                self.modeller.request_close();
                gfx.window.request_redraw();
            }
            WindowEvent::Resized(size) => {
                Self::resize(gfx, size.width, size.height);
                gfx.window.request_redraw();
            }
            WindowEvent::RedrawRequested => {
                let delay = self.redraw();
                self.next_redraw = delay.and_then(|d| Instant::now().checked_add(d));
            }
            WindowEvent::ModifiersChanged(m) => {
                let state = m.state();
                self.modeller
                    .set_modifiers(state.shift_key(), state.control_key());
                gfx.window.request_redraw();
            }
            WindowEvent::CursorMoved { position, .. } => {
                gfx.cursor = Vec2::new(position.x as f32, position.y as f32);
                let cursor = gfx.cursor;
                if owns || !(response.consumed || on_ui(cursor)) {
                    self.pointer(PointerInput::Moved(cursor - origin));
                }
            }
            WindowEvent::CursorLeft { .. } => self.pointer(PointerInput::Left),
            WindowEvent::MouseInput { state, button, .. } => {
                let button = match button {
                    MouseButton::Left => Button::Left,
                    MouseButton::Right => Button::Right,
                    MouseButton::Middle => Button::Middle,
                    _ => return,
                };
                let p = gfx.cursor - origin;
                let on_ui = on_ui(gfx.cursor);
                match state {
                    ElementState::Pressed if !response.consumed && !on_ui => {
                        self.pointer(PointerInput::Pressed(button, p))
                    }
                    ElementState::Released if owns || !response.consumed => {
                        self.pointer(PointerInput::Released(button, p))
                    }
                    _ => {}
                }
            }
            WindowEvent::MouseWheel { delta, .. }
                if !response.consumed && (owns || !on_ui(gfx.cursor)) =>
            {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.pointer(PointerInput::Wheel(steps));
            }
            _ => {}
        }
        if self.modeller.wants_to_quit() {
            self.modeller.on_exit();
            event_loop.exit();
        }
    }

    fn new_events(&mut self, _event_loop: &ActiveEventLoop, _cause: winit::event::StartCause) {
        // An event delivered in this iteration came after the last one read the queue empty:
        // no earlier than that iteration's start (see the module docs, "Timing error").
        let now = self.clock.elapsed().as_secs_f64();
        self.iteration_start = now;
        self.earliest = now - self.last_busy;
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.last_busy = (self.clock.elapsed().as_secs_f64() - self.iteration_start).max(0.0);
        let Some(gfx) = &self.gfx else { return };
        match self.next_redraw {
            Some(t) if t <= Instant::now() => {
                self.next_redraw = None;
                gfx.window.request_redraw();
                event_loop.set_control_flow(ControlFlow::Wait);
            }
            Some(t) => event_loop.set_control_flow(ControlFlow::WaitUntil(t)),
            None => event_loop.set_control_flow(ControlFlow::Wait),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn button(pressed: bool) -> egui::Event {
        egui::Event::PointerButton {
            pos: egui::pos2(10.0, 10.0),
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        }
    }

    /// Arrivals delivered at `times`, each no earlier than it was delivered (no slack).
    fn on_time(times: &[f64]) -> Vec<Arrival> {
        times
            .iter()
            .map(|&t| Arrival { at: t, earliest: t })
            .collect()
    }

    /// Runs frames of queued input through one egui context as the window does (each pass
    /// with its widened click limits, or egui's own limits when `widen` is false); true when
    /// any pass saw a double click.
    fn double_clicked(frames: Vec<(Vec<egui::Event>, Vec<Arrival>, f64)>, widen: bool) -> bool {
        let ctx = egui::Context::default();
        let base = ctx.options(|o| o.input_options);
        let mut double = false;
        for (events, arrivals, now) in frames {
            for pass in input_passes(events, &arrivals, now) {
                let options = if widen {
                    pass.input_options(base)
                } else {
                    base
                };
                ctx.options_mut(|o| o.input_options = options);
                let raw = egui::RawInput {
                    events: pass.events,
                    time: Some(pass.time),
                    ..egui::RawInput::default()
                };
                let _ = ctx.run_ui(raw, |ui| {
                    double |= ui.input(|i| {
                        i.pointer
                            .button_double_clicked(egui::PointerButton::Primary)
                    });
                });
            }
        }
        double
    }

    /// Two clicks 80 ms apart queued during one slow frame are two passes timed 80 ms apart,
    /// and egui counts the second as a double click; text typed after a click gets its own pass.
    #[test]
    fn queued_clicks_and_typing_keep_their_passes() {
        let events = vec![
            button(true),
            button(false),
            button(true),
            button(false),
            egui::Event::Text("ab".into()),
        ];
        let times = on_time(&[1.00, 1.01, 1.09, 1.10, 1.15]);
        let passes = input_passes(events.clone(), &times, 1.3);
        let shape: Vec<usize> = passes.iter().map(|p| p.events.len()).collect();
        assert_eq!(shape, vec![1, 1, 1, 1, 1]);
        assert_eq!(passes[1].time, 1.01);
        assert_eq!(passes[3].time, 1.10);
        assert!(passes.iter().all(|p| p.slack == 0.0), "no slack");
        assert!(
            double_clicked(
                vec![(events[..4].to_vec(), times[..4].to_vec(), 1.3)],
                false
            ),
            "the second click is a double click"
        );

        // Moves and a single click stay in one pass.
        let moved = egui::Event::PointerMoved(egui::pos2(1.0, 1.0));
        let passes = input_passes(
            vec![moved.clone(), button(true), moved, button(false)],
            &on_time(&[0.0; 4]),
            1.0,
        );
        assert_eq!(passes.len(), 2);
    }

    /// Two clicks 80 ms apart that straddle a slow frame: the first is delivered and drawn at
    /// once, the second comes while that frame draws (0.33 s) and is delivered after it. Timed
    /// by delivery they are 0.315 s apart, past egui's 0.3 s; with the slack of the second
    /// (it came no earlier than the iteration that drew the frame began) it is a double click.
    /// Two clicks 0.6 s apart with fast frames stay two clicks.
    #[test]
    fn a_double_click_that_straddles_a_slow_frame_counts() {
        let click = || vec![button(true), button(false)];
        // Iteration j − 1 begins at 0.99, delivers the first click, draws until 1.32.
        let first = (click(), on_time(&[1.00, 1.01]), 1.02);
        // Iteration j begins at 1.32: lo = 1.32 − 0.33.
        let late = |at: f64| Arrival { at, earliest: 0.99 };
        let second = (click(), vec![late(1.325), late(1.33)], 1.335);
        let passes = input_passes(second.0.clone(), &second.1, second.2);
        assert!((passes[1].slack - 0.345).abs() < 1e-9, "{passes:?}");
        assert!(
            !double_clicked(vec![first.clone(), second.clone()], false),
            "egui alone, timed by delivery: two clicks"
        );
        assert!(
            double_clicked(vec![first, second], true),
            "with the slack: a double click"
        );

        // Fast frames (busy 5 ms), the clicks 0.6 s apart: the slack is a few milliseconds.
        let first = (click(), on_time(&[1.00, 1.01]), 1.012);
        let prompt = |at: f64| Arrival {
            at,
            earliest: at - 0.006,
        };
        let second = (click(), vec![prompt(1.60), prompt(1.61)], 1.612);
        assert!(
            !double_clicked(vec![first, second], true),
            "0.6 s apart is two clicks"
        );
    }

    /// Issue 16 item 8: the pointer over the 3D view in the last frame, then moved onto a
    /// toolbar button and pressed before the next frame. egui's answer (from that last frame)
    /// says the pointer is not its own; the position says it is, so the press goes to the
    /// button only and never sculpts.
    #[test]
    fn a_press_that_moved_onto_a_button_within_the_frame_is_the_uis() {
        let ctx = egui::Context::default();
        let screen = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(800.0, 600.0));
        let mut button_rect = egui::Rect::NOTHING;
        let mut window_rect = egui::Rect::NOTHING;
        let mut view = egui::Rect::NOTHING;
        let mut frame = |events: Vec<egui::Event>| {
            let raw = egui::RawInput {
                screen_rect: Some(screen),
                events,
                ..Default::default()
            };
            let _ = ctx.run_ui(raw, |ui| {
                egui::Panel::top("top").show(ui, |ui| {
                    button_rect = ui.button("Open…").rect;
                });
                egui::Panel::left("tools")
                    .exact_size(200.0)
                    .show(ui, |ui| ui.label("tools"));
                let ctx = ui.ctx().clone();
                if let Some(r) = egui::Window::new("Devices")
                    .fixed_pos([550.0, 400.0])
                    .show(&ctx, |ui| ui.label("a floating window"))
                {
                    window_rect = r.response.rect;
                }
                view = ui.available_rect_before_wrap();
            });
        };
        frame(Vec::new());
        let surface = egui::pos2(350.0, 150.0);
        frame(vec![egui::Event::PointerMoved(surface)]);
        frame(vec![egui::Event::PointerMoved(surface)]);
        let viewport = (
            Vec2::new(view.min.x, view.min.y),
            Vec2::new(view.width(), view.height()),
        );
        let px = |p: egui::Pos2| Vec2::new(p.x, p.y);
        assert!(
            !ctx.egui_wants_pointer_input(),
            "over the surface: layer {:?}, view {view:?}, window {window_rect:?}",
            ctx.layer_id_at(surface)
        );
        assert!(!over_ui(&ctx, px(surface), viewport));
        // The stale answer egui-winit would give for a press on the button now.
        assert!(
            !ctx.egui_wants_pointer_input(),
            "stale: still the surface's"
        );
        assert!(
            over_ui(&ctx, px(button_rect.center()), viewport),
            "the toolbar button"
        );
        assert!(
            over_ui(&ctx, Vec2::new(50.0, 300.0), viewport),
            "the tool panel"
        );
        assert!(
            over_ui(&ctx, px(window_rect.center()), viewport),
            "a floating window over the view"
        );
    }
}

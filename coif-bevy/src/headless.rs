//! Rendering without a window (feature `render`): a camera drawing into an
//! [`Image`] render target, read back to the CPU with Bevy's
//! [`Screenshot`], for tests and pictures (`tests/render.rs`, the `sintel`
//! example's `--headless --screenshot`).
//!
//! An app builds its plugins with no primary window and without
//! `WinitPlugin`, calls [`finish_plugins`] (the renderer starts
//! asynchronously), then `update`s itself: [`Capture::request`] asks for
//! the target's pixels, which arrive a frame or two later in
//! [`Capture::image`].

use bevy::app::PluginsState;
use bevy::asset::RenderAssetUsages;
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};

/// The name of the first GPU adapter wgpu finds (any backend Bevy's
/// renderer is built with: Vulkan here, e.g. Mesa's lavapipe, `llvmpipe`),
/// or `None`: without one Bevy's renderer would panic at start-up, so a
/// caller checks first.
pub fn gpu_adapter() -> Option<String> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let options = wgpu::RequestAdapterOptions::default();
    let adapter = bevy::tasks::block_on(instance.request_adapter(&options)).ok()?;
    Some(adapter.get_info().name)
}

/// An sRGB RGBA8 image a camera can render into and a [`Screenshot`] can
/// copy from, `width x height` (each at least 1).
pub fn target_image(width: u32, height: u32) -> Image {
    let mut image = Image::new_target_texture(
        width.max(1),
        height.max(1),
        TextureFormat::Rgba8UnormSrgb,
        None,
    );
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    image.asset_usage = RenderAssetUsages::RENDER_WORLD;
    image
}

/// The camera's target for an image handle.
pub fn image_target(image: Handle<Image>) -> RenderTarget {
    RenderTarget::Image(image.into())
}

/// Waits until every plugin is ready (Bevy's renderer initialises its
/// device on a task), then finishes and cleans up the plugins, as an app's
/// runner does before its first update.
pub fn finish_plugins(app: &mut App) {
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
        std::thread::yield_now();
    }
    app.finish();
    app.cleanup();
}

/// The last pixels read back from a render target.
#[derive(Resource, Default, Debug)]
pub struct Capture {
    /// The image of the last finished capture.
    pub image: Option<Image>,
    /// A capture was requested and has not arrived.
    pub pending: bool,
}

impl Capture {
    /// Asks for `target`'s pixels after this frame is rendered; they arrive
    /// in the [`Capture`] resource (inserted if missing).
    pub fn request(commands: &mut Commands, target: Handle<Image>) {
        commands.queue(|world: &mut World| {
            let mut capture = world.get_resource_or_insert_with(Capture::default);
            capture.pending = true;
            capture.image = None;
        });
        commands.spawn(Screenshot::image(target)).observe(
            |captured: On<ScreenshotCaptured>, mut capture: ResMut<Capture>| {
                capture.image = Some(captured.image.clone());
                capture.pending = false;
            },
        );
    }
}

/// An image's pixels as tightly packed RGBA8 (sRGB as stored), row after
/// row, with its size; `None` for formats other than RGBA8 / BGRA8 or an
/// image without CPU data.
pub fn rgba8(image: &Image) -> Option<(u32, u32, Vec<u8>)> {
    let size = image.texture_descriptor.size;
    let (w, h) = (size.width, size.height);
    let data = image.data.as_ref()?;
    let n = (w as usize) * (h as usize) * 4;
    if data.len() < n {
        return None;
    }
    match image.texture_descriptor.format {
        TextureFormat::Rgba8Unorm | TextureFormat::Rgba8UnormSrgb => {
            Some((w, h, data[..n].to_vec()))
        }
        TextureFormat::Bgra8Unorm | TextureFormat::Bgra8UnormSrgb => {
            let mut out = data[..n].to_vec();
            for px in out.chunks_exact_mut(4) {
                px.swap(0, 2);
            }
            Some((w, h, out))
        }
        _ => None,
    }
}

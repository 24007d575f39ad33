//! `docs/adding-a-strategy.md`, kept true. Its example mapping (`thread-kahan`) is read from the
//! guide's own code blocks (the WGSL file and the registry line), composed through the solver's
//! composer with the defines of every variant of its layout, validated by naga, compiled against
//! the solver's explicit bind-group layout and run on the GPU (lavapipe here): each pair-sum
//! stage on the CPU reference's inputs for that stage, its outputs poisoned first, compared with
//! the CPU's outputs by `sphlab verify`'s measure and tolerances. Also: every repository path the
//! guide names exists, and every relative link of README.md, docs/*.md and reports/README.md
//! resolves inside the repository.

mod common;

use common::{assert_fields_match, gpu_or_skip, scene, serial};
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::fields::{Field, Fields};
use sphlab::gpu::compose::{compose_mapped, validate};
use sphlab::gpu::params::Params;
use sphlab::gpu::solver_buffers::{self, Bufs};
use sphlab::gpu::stages::{defines, PAIR_STAGES};
use sphlab::gpu::variant::{Accumulation, KernelValues, Mapping, SumLayout, VariantSpec, Workgroup};
use sphlab::gpu::variant_buffers::{self, VBufs};
use sphlab::gpu::GpuContext;
use sphlab::neighbours::cells::CellBox;
use sphlab::neighbours::SearchKind;
use sphlab::real::Precision;
use sphlab::real::{Real, V2};
use sphlab::stage::Stage;
use sphlab::verify::compare_fields;
use std::path::{Path, PathBuf};

const GUIDE: &str = "docs/adding-a-strategy.md";

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(repo().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The fenced code blocks of a Markdown text: (language, body).
fn code_blocks(md: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut open: Option<(String, String)> = None;
    for line in md.lines() {
        match (line.trim_start().strip_prefix("```"), open.take()) {
            (Some(lang), None) => open = Some((lang.trim().to_string(), String::new())),
            (Some(_), Some(block)) => out.push(block),
            (None, Some((lang, mut body))) => {
                body.push_str(line);
                body.push('\n');
                open = Some((lang, body));
            }
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "an unclosed code block");
    out
}

/// The guide's mapping: its file (from the WGSL block's first line), source and registry line.
struct Toy {
    /// Path under `kernels-variants/`.
    file: String,
    source: String,
    id: String,
    registry_file: String,
    layout: String,
}

fn toy() -> Toy {
    let blocks = code_blocks(&read(GUIDE));
    let (_, source) = blocks.iter().find(|(l, _)| l == "wgsl").expect("the guide has a ```wgsl block").clone();
    let first = source.lines().next().unwrap_or("");
    let file = first
        .trim_start_matches("//")
        .trim()
        .split(':')
        .next()
        .and_then(|p| p.strip_prefix("kernels-variants/"))
        .unwrap_or_else(|| panic!("the WGSL block must open with `// kernels-variants/<path>: …`, not {first:?}"))
        .to_string();
    // `Variant = "id": Some("file"), Layout;`
    let line = blocks
        .iter()
        .filter(|(l, _)| l == "rust")
        .flat_map(|(_, b)| b.lines().map(str::trim).map(String::from).collect::<Vec<_>>())
        .find(|l| !l.starts_with("//") && l.contains("\": Some(\""))
        .expect("the guide has a registry line `Variant = \"id\": Some(\"file\"), Layout;`");
    let quoted: Vec<&str> = line.split('"').collect();
    assert!(quoted.len() == 5, "registry line {line:?}");
    let layout = quoted[4].trim_start_matches(')').trim_start_matches(',').trim().trim_end_matches(';').to_string();
    Toy { file, source, id: quoted[1].to_string(), registry_file: quoted[3].to_string(), layout }
}

/// The defines of every search × kernel values × precision of a layout, as the solver would
/// compose the new mapping's file: taken from an already registered mapping of the same layout
/// (`stages::defines` depends on the layout, not on the mapping's name).
fn variants_of_layout(layout: SumLayout) -> Vec<VariantSpec> {
    let twin = *Mapping::ALL.iter().find(|m| m.layout() == layout).expect("a registered mapping of this layout");
    VariantSpec::all().into_iter().filter(|s| s.mapping == twin).collect()
}

fn layout_named(name: &str) -> SumLayout {
    match name {
        "Thread" => SumLayout::Thread,
        "Block" => SumLayout::Block,
        "Subgroup" => SumLayout::Subgroup,
        other => panic!("registry line names the layout {other:?}, not one of Thread, Block, Subgroup"),
    }
}

/// Steps 1 and 2: the registry line and the file agree, the id is new, and the file composes and
/// validates for every variant of its layout with one entry point per pair-sum stage.
#[test]
fn guide_mapping_composes_and_validates_for_every_variant_of_its_layout() {
    let t = toy();
    assert_eq!(t.registry_file, t.file, "the registry line names the file the WGSL block says it is");
    assert!(
        Mapping::ALL.iter().all(|m| m.name() != t.id),
        "`{}` is already a registered mapping: the guide's example must be a new one",
        t.id
    );
    let layout = layout_named(&t.layout);
    assert_eq!(layout, SumLayout::Thread, "tests below dispatch the example as one thread per particle");
    let specs = variants_of_layout(layout);
    assert_eq!(specs.len(), 12, "3 searches × 2 kernel values × 2 precisions");
    for spec in specs {
        let defs = defines(&spec);
        let c = compose_mapped(&format!("kernels-variants/{}", t.file), &t.source, &defs)
            .unwrap_or_else(|e| panic!("{}: {e}", t.file));
        let m = validate(&c).unwrap_or_else(|e| panic!("{} with {defs:?}: {e}", t.file));
        for (stage, _) in PAIR_STAGES {
            let name = stage.name();
            assert!(m.entry_points.iter().any(|e| e.name == name), "{}: no entry point `{name}`", t.file);
        }
    }
}

/// `T::NAME` as a precision.
fn precision<T: Real>() -> Precision {
    if T::NAME == "f64" {
        Precision::F64
    } else {
        Precision::F32
    }
}

/// The solver's group-0 state and group-1 strategy buffers for the CPU solver's particles.
struct Device<T: Real> {
    b: Bufs<T>,
    groups: [wgpu::BindGroup; 2],
    layout: wgpu::PipelineLayout,
}

impl<T: Real> Device<T> {
    fn new(ctx: &GpuContext, cpu: &CpuSolver<T>, spec: VariantSpec) -> Self {
        let n = cpu.pos.len();
        let grid = CellBox::over(&cpu.pos, cpu.model.support());
        let params = Params::new(&cpu.model, n, cpu.n_fluid, &grid);
        let b = Bufs::new(ctx, &params, n, grid.cells()).expect("state buffers");
        let vb = VBufs::new(ctx, spec, &cpu.model, n, grid.cells()).expect("strategy buffers");
        let (state, _) = solver_buffers::layouts(ctx).expect("state layout");
        let (strategy, layout) = variant_buffers::layouts(ctx, &state).expect("pipeline layout");
        let groups =
            [b.bind_group(ctx, &state).expect("group 0"), vb.bind_groups(ctx, &strategy).expect("group 1").remove(0)];
        b.pos().upload(ctx, &cpu.pos).unwrap();
        b.vel().upload(ctx, &cpu.vel).unwrap();
        b.phase.upload(ctx, &cpu.phase).unwrap();
        Self { b, groups, layout }
    }

    /// The inputs of a stage (every field, as `GpuSolver::run_stage_from` uploads them), then
    /// NaN in the stage's outputs.
    fn load(&self, ctx: &GpuContext, f: &Fields<T>, stage: Stage) {
        let b = &self.b;
        b.sigma().upload(ctx, &solver_buffers::sigma_pairs(&f.sigma)).unwrap();
        b.chi.upload(ctx, &f.chi).unwrap();
        b.mass().upload(ctx, &f.mass).unwrap();
        b.colour.upload(ctx, &f.colour).unwrap();
        b.rho().upload(ctx, &f.rho).unwrap();
        b.p.upload(ctx, &f.p).unwrap();
        b.grad0().upload(ctx, &f.grad.iter().map(|g| g[0]).collect::<Vec<_>>()).unwrap();
        b.grad1().upload(ctx, &f.grad.iter().map(|g| g[1]).collect::<Vec<_>>()).unwrap();
        b.pi().upload(ctx, &f.pi.iter().map(|t| V2::new(t.xx, t.xy)).collect::<Vec<_>>()).unwrap();
        b.acc.upload(ctx, &f.acc).unwrap();
        let (nan, nan2) = (T::nan(), V2::new(T::nan(), T::nan()));
        for field in stage.pure_outputs() {
            match field {
                Field::Sigma => b.sigma().fill(ctx, nan2).unwrap(),
                Field::Chi => b.chi.fill(ctx, nan).unwrap(),
                Field::Grad => {
                    b.grad0().fill(ctx, nan2).unwrap();
                    b.grad1().fill(ctx, nan2).unwrap();
                }
                Field::Acc => b.acc.fill(ctx, nan2).unwrap(),
                other => panic!("{stage} writes {other:?}, which this test does not read back"),
            }
        }
    }

    /// `f` with the stage's outputs replaced by the device's.
    fn outputs(&self, ctx: &GpuContext, f: &Fields<T>, stage: Stage) -> Fields<T> {
        let mut g = f.clone();
        for field in stage.outputs() {
            match field {
                Field::Sigma => g.sigma = solver_buffers::sigma_of(self.b.sigma().read_back(ctx).unwrap()),
                Field::Chi => g.chi = self.b.chi.read_back(ctx).unwrap(),
                Field::Grad => {
                    let (a, c) = (self.b.grad0().read_back(ctx).unwrap(), self.b.grad1().read_back(ctx).unwrap());
                    g.grad = a.into_iter().zip(c).map(|(a, c)| [a, c]).collect();
                }
                Field::Acc => g.acc = self.b.acc.read_back(ctx).unwrap(),
                other => panic!("{stage} writes {other:?}, which this test does not read back"),
            }
        }
        g
    }

    /// One dispatch of `entry` over `groups` workgroups of 64 threads, waited for.
    fn dispatch(&self, ctx: &GpuContext, module: &wgpu::ShaderModule, entry: &str, groups: u32) {
        let pipeline = ctx
            .scoped(|d| {
                d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&self.layout),
                    module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
            .unwrap_or_else(|e| panic!("`{entry}` against the solver's layout: {e}"));
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &self.groups[0], &[]);
            pass.set_bind_group(1, &self.groups[1], &[]);
            pass.dispatch_workgroups(groups, 1, 1);
        }
        ctx.queue.submit([enc.finish()]);
        ctx.wait_idle().expect("dispatch");
    }
}

/// Runs every active pair-sum stage of the guide's mapping on the CPU's inputs for it and
/// compares its outputs with the CPU's; checks once that an unwritten half fails the comparison.
fn check_scene<T: Real>(ctx: &GpuContext, t: &Toy, name: &str, sets: &[&str]) -> usize {
    let (s, l) = scene(name, sets);
    let mut cpu = CpuSolver::<T>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
    let snaps = cpu.evaluate_stagewise().expect("CPU evaluation");
    // The direct search needs no search structures on the device: the example's kernels walk
    // every particle under every image code, the neighbour set of the CPU's cell search.
    let spec = VariantSpec {
        search: SearchKind::Direct,
        mapping: Mapping::Thread,
        accumulation: Accumulation::None,
        kernel_values: KernelValues::Recomputed,
        precision: precision::<T>(),
        workgroup: Workgroup::W64,
        lists: sphlab::gpu::variant::ListFormat::Auto,
        slots: sphlab::gpu::variant::SlotLayout::Auto,
    };
    let composed = compose_mapped(&t.file, &t.source, &defines(&spec)).expect("composes");
    let module = ctx
        .scoped(|d| {
            d.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&t.file),
                source: wgpu::ShaderSource::Wgsl(composed.source.clone().into()),
            })
        })
        .expect("the driver accepts the module");
    let dev = Device::new(ctx, &cpu, spec);
    let n = cpu.pos.len();
    let groups = n.div_ceil(64) as u32;
    let mut ran = 0;
    for (stage, _) in PAIR_STAGES {
        let Some(k) = snaps.iter().position(|(s, _)| *s == stage) else { continue };
        let (input, want) = (&snaps[k - 1].1, &snaps[k].1);
        let only: Vec<Field> = stage.outputs().collect();
        dev.load(ctx, input, stage);
        dev.dispatch(ctx, &module, stage.name(), groups);
        let got = dev.outputs(ctx, input, stage);
        let tag = format!("{} {name} {} [{}]", t.id, stage, T::NAME);
        assert_fields_match(&tag, &cpu.model, cpu.n_fluid, want, &got, Some(&only));
        if ran == 0 {
            // The comparison can fail: half the workgroups leave half the particles poisoned.
            dev.load(ctx, input, stage);
            dev.dispatch(ctx, &module, stage.name(), groups.div_ceil(2));
            let half = dev.outputs(ctx, input, stage);
            let checks = compare_fields("field", "", &half, want, &cpu.model, cpu.n_fluid, Some(&only));
            assert!(checks.iter().any(|c| !c.pass), "{tag}: a half-written output must fail the comparison");
        }
        ran += 1;
    }
    ran
}

/// Step 5 on the example: its three pair-sum stages on the GPU against the CPU reference, on the
/// oscillating drop (mirror images, two fluids) and the 90° sessile drop in Mode B (walls typed
/// by the contact line, no-slip ghost velocities), in f32 and, where the adapter has it, f64.
#[test]
fn guide_mapping_matches_the_cpu_reference_on_the_gpu() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let t = toy();
    let scenes: [(&str, &[&str]); 2] =
        [("oscillating-drop", &["domain.nx=20"]), ("sessile-90", &["contact.mode=b", "domain.nx=21"])];
    let mut ran = 0;
    for (name, sets) in scenes {
        ran += check_scene::<f32>(&ctx, &t, name, sets);
        if ctx.has(wgpu::Features::SHADER_F64) {
            ran += check_scene::<f64>(&ctx, &t, name, sets);
        } else {
            println!("f64 not checked: the adapter lacks SHADER_F64");
        }
    }
    assert!(ran >= 6, "every pair-sum stage ran on both scenes ({ran} stage runs)");
}

/// Backticked repository paths in a Markdown text: `dir/…` under a top-level folder of the
/// repository, or a file at its root; placeholders (`<…>`, `{…}`, `*`) are left out.
fn named_paths(md: &str) -> Vec<String> {
    const TOP: [&str; 12] = [
        "core/",
        "examples/",
        "src/",
        "shaders/",
        "kernels-variants/",
        "tests/",
        "docs/",
        "benches/",
        "scripts/",
        "reports/",
        "scenes/",
        "data/",
    ];
    md.split('`')
        .skip(1)
        .step_by(2)
        .map(|s| s.split("::").next().unwrap_or(s).trim_end_matches(',').to_string())
        .filter(|s| !s.contains(['<', '{', '*', ' ']))
        .filter(|s| {
            TOP.iter().any(|t| s.starts_with(t)) || ["Cargo.toml", "README.md", "build.rs"].contains(&s.as_str())
        })
        .collect()
}

/// A path as the docs write it, on this checkout.
fn on_disk(p: &str) -> PathBuf {
    repo().join(p)
}

/// Paths the docs name that a command creates, not the repository: the GPU loan's report.
const CREATED_BY_COMMANDS: [&str; 1] = ["reports/gpu/"];

/// The paths named by `md` that do not exist, leaving out `exempt` (files the text tells the
/// reader to create) and [`CREATED_BY_COMMANDS`].
fn missing_paths(md: &str, exempt: &[String]) -> Vec<String> {
    named_paths(md)
        .into_iter()
        .filter(|p| !exempt.iter().any(|e| p.starts_with(e.as_str())))
        .filter(|p| !CREATED_BY_COMMANDS.iter().any(|c| p.starts_with(c)))
        .filter(|p| !on_disk(p).exists())
        .collect()
}

#[test]
fn every_path_the_guide_names_exists() {
    let t = toy();
    let md = read(GUIDE);
    let paths = named_paths(&md);
    assert!(paths.len() >= 20, "the guide names its files ({} found)", paths.len());
    let new_file = format!("kernels-variants/{}", t.file);
    let missing = missing_paths(&md, &[new_file.clone(), format!("kernels-variants/{}/", t.id)]);
    assert!(missing.is_empty(), "{GUIDE} names paths that do not exist: {missing:?}");
    assert!(!on_disk(&new_file).exists(), "{new_file} is the example the guide creates; it must not be in the tree");
}

/// The same for the README, the other docs and the reports' README.
#[test]
fn every_path_the_docs_name_exists() {
    let root = repo();
    let mut bad = Vec::new();
    for file in markdown_files() {
        let md = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        if file.ends_with(GUIDE) {
            continue;
        }
        for p in missing_paths(&md, &[]) {
            bad.push(format!("{}: `{p}`", file.strip_prefix(&root).unwrap_or(&file).display()));
        }
    }
    assert!(bad.is_empty(), "paths named in the docs that do not exist:\n{}", bad.join("\n"));
}

/// GitHub's anchor of a heading: lower case, punctuation dropped, spaces as hyphens.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

fn anchors(md: &str) -> Vec<String> {
    md.lines().filter(|l| l.starts_with('#')).map(|l| anchor(l.trim_start_matches('#'))).collect()
}

/// The targets of the inline links `[text](target)` of a Markdown text, outside code blocks.
fn links(md: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in md.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut rest = line;
        while let Some(k) = rest.find("](") {
            let tail = &rest[k + 2..];
            let end = tail.find(')').unwrap_or(tail.len());
            out.push(tail[..end].trim().to_string());
            rest = &tail[end..];
        }
    }
    out
}

fn markdown_files() -> Vec<PathBuf> {
    let root = repo();
    let mut files =
        vec![root.join("README.md"), root.join("reports/README.md"), root.join("reports/validation/index.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// The relative links of `md` (the text of `file`) that do not resolve to a file inside the
/// repository, or to a heading of it where they carry an anchor.
fn unresolved(file: &Path, md: &str) -> Vec<String> {
    let root = repo().canonicalize().expect("repository root");
    let dir = file.parent().expect("a folder");
    let mut bad = Vec::new();
    for target in links(md) {
        if target.starts_with("http://") || target.starts_with("https://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, frag) = target.split_once('#').unwrap_or((&target, ""));
        let resolved = if path.is_empty() { file.to_path_buf() } else { dir.join(path) };
        let inside = resolved.canonicalize().is_ok_and(|p| p.starts_with(&root));
        let anchored = frag.is_empty()
            || resolved.extension().is_none_or(|x| x != "md")
            || std::fs::read_to_string(&resolved).is_ok_and(|t| anchors(&t).iter().any(|a| a == frag));
        if !inside || !anchored {
            bad.push(target);
        }
    }
    bad
}

#[test]
fn every_relative_link_resolves_inside_the_repository() {
    let root = repo();
    let mut bad = Vec::new();
    let mut count = 0;
    for file in markdown_files() {
        let md = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        count += links(&md).len();
        for target in unresolved(&file, &md) {
            bad.push(format!("{}: ({target})", file.strip_prefix(&root).unwrap_or(&file).display()));
        }
    }
    assert!(count >= 40, "links found: {count}");
    assert!(bad.is_empty(), "links that do not resolve inside the repository:\n{}", bad.join("\n"));
}

/// The link and path checks themselves: a link out of the repository, a missing file and a
/// missing anchor are caught, a good link and anchor pass; a placeholder is not taken for a path.
#[test]
fn the_checks_catch_what_they_are_for() {
    let md = "[a](../outside.md) [b](nope.md) [c](#no-such-heading) [d](PHYSICS.md#0-notation-and-signs) `src/<name>.rs` `tests/guide.rs` `src/nope.rs`";
    assert_eq!(links(md).len(), 4);
    let file = repo().join("docs/example.md");
    assert_eq!(unresolved(&file, md), ["../outside.md", "nope.md", "#no-such-heading"]);
    assert_eq!(named_paths(md), ["tests/guide.rs", "src/nope.rs"]);
    assert_eq!(missing_paths(md, &[]), ["src/nope.rs"]);
    assert_eq!(anchor(" Running on a borrowed GPU"), "running-on-a-borrowed-gpu");
    assert_eq!(anchor("(a) Add a thread mapping"), "a-add-a-thread-mapping");
    assert!(on_disk("core/src/stage.rs").exists());
}

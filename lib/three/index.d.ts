// Types of mrvol/three (lib/three/index.mjs): volume-preserving cage editing as a three.js component.
import * as THREE from 'three';
import type { Mrvol, Mesh, MultiresMesh, VolumeEditor, Theta, EditReport, ThetaEstimate, VolumeSurface,
  QuadMesh, QuadMultiresMesh, QuadVolumeEditor } from '../index.js';

export interface VolumeEditControlsOptions {
  /** Cage level e (0..levels of the mesh), default 0. */
  level?: number;
  /** Wavelet scheme: 'loop' (default), 'butterfly', 'linear'; a quad mesh always uses 'catmull-clark'. */
  scheme?: 'loop' | 'butterfly' | 'linear' | 'catmull-clark';
  /** Keep the volume on every move (default true). */
  preserve?: boolean;
  /** Relative volume error the correction stops at (default 1e-6). */
  tolerance?: number;
  /**
   * Gradients: unset (default: the cage polynomial where the cage is coarse against the mesh, as
   * createEditor's 'auto' picks it, else matrix-free), 'matrix-free' (a pass over the fine mesh at
   * every step), 'auto' (compute theta^e now, synchronously, when its estimate fits), or a Theta of
   * this mesh, scheme and level (the component owns it then: dispose() deletes it).
   */
  theta?: 'matrix-free' | 'auto' | Theta;
  /** How near (CSS pixels) the pointer must press to a handle to grab it (default 10). */
  pickRadius?: number;
  surfaceColor?: THREE.ColorRepresentation;
  cageColor?: THREE.ColorRepresentation;
  /**
   * Handle dot size: 'auto' (default) sizes the dots to the cage's density on the screen,
   * clamp(0.55 x the median on-screen cage edge length, 6, 13) CSS pixels (AUTO_HANDLE_SIZE),
   * measured again when the camera, the element's size or the cage changed: a cage of 600 handles
   * seen whole on a phone gets small dots, zoomed in they grow back to 13 px. A number: that size
   * in CSS pixels, fixed. Either way a handle behind the surface is drawn faint (the hovered and
   * the dragged one at full strength), and pickRadius, not the dot, decides what a press grabs.
   */
  handleSize?: 'auto' | number;
  /** Flat shading (default true). */
  flat?: boolean;
}

export interface VolumeEditControlsEventMap {
  /** A handle was grabbed and moved for the first time. */
  dragstart: { handle: number };
  /** One drag step: the core's report of it (volumes, iterations, path). */
  drag: { handle: number; report: EditReport };
  /** The drag ended (cancelled: the cage went back). */
  dragend: { handle?: number; cancelled: boolean };
  /** Something to draw changed (render on it); report: the drag step's, else null. */
  change: { report: EditReport | null; reason: 'drag' | 'dragend' | 'move' | 'undo' | 'redo' | 'cancel' | 'hover' | 'level' };
  /** An edit was refused and undone (e.g. a fixed boundary vertex). */
  error: { message: string; error: Error };
}

/**
 * The editor for any scene: `object` (fine surface, cage edges, handles) goes into the host's
 * scene; the pointer drags handles on the camera-facing plane; the volume is restored on each move.
 * Renders nothing: render on `change`. dispose() frees its WASM memory and listeners.
 */
export class VolumeEditControls extends THREE.EventDispatcher<VolumeEditControlsEventMap> {
  constructor(mrvol: Mrvol, camera: THREE.Camera, element: HTMLElement | { domElement: HTMLElement },
    mesh: Mesh | MultiresMesh | QuadMesh | QuadMultiresMesh, options?: VolumeEditControlsOptions);
  readonly object: THREE.Group;
  readonly surface: SurfaceMesh;
  readonly cage: CageObject;
  readonly session: EditingSession;
  readonly camera: THREE.Camera;
  readonly domElement: HTMLElement;
  /** false: the pointer is ignored (a host's own tool is active). */
  enabled: boolean;
  pickRadius: number;
  preserve: boolean;
  readonly level: number;
  readonly dragging: boolean;
  readonly handleCount: number;
  /** The handleSize option: 'auto' or the fixed size (CSS pixels). */
  readonly handleSize: 'auto' | number;
  /** The dot size (CSS pixels) for the camera and the element now ('auto': from the cage's screen spacing, 6..13). */
  readonly handlePixelSize: number;
  readonly lastReport: EditReport | null;
  volume(): number;
  referenceVolume(): number;
  positions(): Float64Array;
  cagePositions(): Float64Array;
  /** Another cage level; the shape and the reference volume stay, the history is cleared. */
  setLevel(level: number): void;
  /**
   * Moves handles (cage vertices, cage order) by `delta` from code, as one drag: the volume restored,
   * one undo step, the picture redrawn, `change` with reason 'move'. null when refused (`error` event).
   */
  moveHandles(handles: number[], delta: [number, number, number] | number[]): EditReport | null;
  undo(): boolean;
  redo(): boolean;
  /** Abandons the drag going on; true if there was one. */
  cancel(): boolean;
  /** [x0, y0, x1, y1, ...]: handles on the element, CSS pixels from its top left. */
  handleScreenPositions(): number[];
  /** Frees its WASM memory, buffers and listeners; a second call does nothing, any other call after it throws MrvolError. */
  dispose(): void;
}

/** The free-set modes of an EditingSession. */
export const FREE_SET_MODES: readonly ['minus-held', 'all', 'painted', 'parts'];
export const MAX_PARTS: 8;
/** The scheme of quad models. */
export const QUAD_SCHEME: 'catmull-clark';
export type FreeSetMode = 'minus-held' | 'all' | 'painted' | 'parts';

export interface FreeSet {
  mode: FreeSetMode;
  /** Caller's cage vertices free for the correction (mode 'painted'). */
  painted: number[];
  /** MAX_PARTS lists of caller's cage vertices; each non-empty one keeps its volume (mode 'parts'). */
  parts: number[][];
}

/**
 * The DOM-free editing session (no three.js either) the component and the web editor are built
 * on: model, editor, undo history, free set and parts, the tensor in use. Events (CustomEvent
 * detail): model, editor ({ level, scheme }), step ({ report, ms }), change ({ reason }), theta
 * ({ source, path }), dragend, error ({ message, error }), history-full ({ limit }: the undo history held
 * historyLimit steps, 200 by default, and let the oldest go).
 */
export class EditingSession extends EventTarget {
  constructor(mrvol: Mrvol, options?: { level?: number; scheme?: string; alpha?: number; beta?: number;
    preserve?: boolean; tolerance?: number; historyLimit?: number });
  readonly mrvol: Mrvol;
  /** faces: triangles (a quad model's quads split in two for drawing); quads: a quad model's quads, else null. */
  model: { name: string; mr: MultiresMesh | QuadMultiresMesh; info: ReturnType<MultiresMesh['info']>; fingerprint: string;
    faces: Uint32Array; quads: Uint32Array | null; depths: Uint32Array } | null;
  editor: VolumeEditor | QuadVolumeEditor | null;
  /** A quad model (catmull-clark scheme, bilinear-patch volume, a cage of quads). */
  readonly quad: boolean;
  /** The free-set modes the editor takes (a quad editor: fewer). */
  readonly freeSetModes: readonly FreeSetMode[];
  readonly canKeepCentroid: boolean;
  readonly canKeepLimit: boolean;
  level: number;
  scheme: string;
  alpha: number;
  beta: number;
  preserve: boolean;
  tolerance: number;
  /** Whose volume is kept ('limit': the Loop limit surface), and whether the centre of mass is kept too. */
  readonly surface: VolumeSurface;
  readonly keepCentroid: boolean;
  readonly cageSize: number;
  readonly cageVertices: Uint32Array | null;
  readonly cageIndex: Map<number, number> | null;
  readonly freeSet: FreeSet;
  readonly parts: number[];
  readonly partReferences: number[] | null;
  readonly thetaSource: string | null;
  readonly lastReport: EditReport | null;
  readonly lastStepMs: number | null;
  readonly dragging: boolean;
  readonly history: { readonly size: { undo: number; redo: number }; readonly canUndo: boolean; readonly canRedo: boolean };
  readonly schemeOptions: { scheme: string; alpha: number; beta: number };
  /** Opens a mesh (owned) or a MultiresMesh (the caller's unless own); throws MrvolError, keeping the current model. */
  open(source: Mesh | MultiresMesh | QuadMesh | QuadMultiresMesh, options?: { name?: string; restore?: { positions?: Float64Array | null; reference?: number } | null;
    own?: boolean }): NonNullable<EditingSession['model']>;
  setLevel(level: number): void;
  setScheme(scheme: string): void;
  /**
   * Level and scheme changed with the editor made elsewhere: this model's mesh opened in another
   * instance of the module at the current shape, its first createEditor at `after` made already
   * (Mrvol.adoptTransferred). One undo step unless record is false; shape, reference, history kept.
   */
  adoptRebuilt(mesh: MultiresMesh, after: { level: number; scheme: string }, options?: { record?: boolean }): void;
  /** Rebuilds the editor for that surface (its reference: that surface's volume now); throws MrvolError, unchanged, for an open mesh. */
  setSurface(surface: VolumeSurface): void;
  /** Keeps the centre of mass where it is now, or stops (mesh surface only). */
  setKeepCentroid(on: boolean): void;
  centroid(): Float64Array | null;
  referenceCentroid(): Float64Array | null;
  /** The level-e cage's edges (pairs of cage indices; a quad cage: the quads' sides, no diagonals). */
  cageEdges(): Uint32Array;
  /** The level-e faces in cage indices: triangles or quads. */
  cageFaces(): { corners: 3 | 4; faces: Uint32Array };
  setFreeSet(freeSet: Partial<FreeSet>, options?: { quiet?: boolean }): void;
  partVolumes(): number[] | null;
  beginDrag(handles: number[]): void;
  /** One step: the handles at their start + delta, volume restored; null when refused (error event). */
  dragBy(delta: [number, number, number] | number[]): EditReport | null;
  endDrag(): void;
  cancelDrag(): void;
  /** The whole cage to `target` (cage order), `held` flags staying put; one step, null when refused. */
  setCage(target: Float64Array, held: ArrayLike<number>): EditReport | null;
  moveHandles(handles: number[], delta: number[]): EditReport | null;
  undo(): boolean;
  redo(): boolean;
  setReferenceVolume(volume?: number): void;
  /** The volume now: the core's pass over the fine mesh, asked once per shape. */
  volume(): number | null;
  /** For readouts: during a drag the last step's own volume (equal to volume() to round-off, without a pass over the mesh); else volume(). */
  volumeNow(): number | null;
  referenceVolume(): number | null;
  positions(): Float64Array;
  cagePositions(): Float64Array;
  approximation(level: number, positions?: Float64Array): Float64Array;
  gradientChoice(): { path: 'tensor' | 'matrix-free'; estimate: ThetaEstimate | null; reason?: string };
  storedTheta(): { theta: Theta; source: string } | null;
  /** The session owns an accepted theta until the model changes. */
  useTheta(theta: Theta, source?: string): { ok: true } | { ok: false; reason: string };
  forgetTheta(): void;
  computeTheta(): { ok: true } | { ok: false; reason: string };
  dispose(): void;
}

/** A shaded surface whose positions change (same vertices). */
export class SurfaceMesh extends THREE.Mesh<THREE.BufferGeometry, THREE.MeshStandardMaterial> {
  constructor(positions: ArrayLike<number>, faces: ArrayLike<number>, options?: { color?: THREE.ColorRepresentation;
    colors?: ArrayLike<number> | null; flat?: boolean; opacity?: number; material?: THREE.MeshStandardMaterial | null });
  static material(options?: { color?: THREE.ColorRepresentation; vertexColors?: boolean; flat?: boolean; opacity?: number }): THREE.MeshStandardMaterial;
  setPositions(positions: ArrayLike<number>): void;
  setColors(colors: ArrayLike<number>): void;
  clearColors(): void;
  dispose(): void;
}

/**
 * lines: edges seen; hidden: edges through the surface (0.22 opacity); handles: dots where seen
 * (depth-tested); hiddenHandles: dots through the surface (no depth test, colours with alpha).
 */
export interface CageMaterials { lines: THREE.LineBasicMaterial; hidden: THREE.LineBasicMaterial; handles: THREE.PointsMaterial | null;
  hiddenHandles: THREE.PointsMaterial | null }

/**
 * A cage: edges seen and through the surface, a coloured dot per handle, drawn at full strength
 * where seen and faint (HIDDEN_HANDLE_OPACITY) through the surface. handleSize 'auto' (default):
 * sized to the cage's spacing on the screen before each frame that changed the view or the cage.
 */
export class CageObject extends THREE.Group {
  constructor(positions: ArrayLike<number>, edges: ArrayLike<number>, options?: { color?: THREE.ColorRepresentation;
    handles?: boolean; handleSize?: 'auto' | number; opacity?: number; materials?: CageMaterials | null });
  /** handleSize: the materials' initial dot size (CSS pixels; an 'auto' cage sets it before it draws). */
  static materials(options?: { color?: THREE.ColorRepresentation; handleSize?: number; opacity?: number; points?: boolean }): CageMaterials;
  readonly count: number;
  readonly positions: Float64Array;
  /** The edges (pairs of handle indices). */
  readonly edges: Uint32Array;
  readonly baseColor: THREE.Color;
  /** The dots where seen (null without handles). */
  readonly handles: THREE.Points | null;
  /** The dots through the surface (null without handles). */
  readonly hiddenHandles: THREE.Points | null;
  /** 'auto' or the fixed dot size (CSS pixels). */
  readonly handleSize: 'auto' | number;
  /** The dot size (CSS pixels) last drawn or measured. */
  readonly handlePixelSize: number;
  /** The dot size for a camera on a width x height CSS-pixel view, set on the materials (measured again only when something changed). */
  updateHandleSize(camera: THREE.Camera, width: number, height: number, options?: { matrices?: boolean }): number;
  setPositions(positions: ArrayLike<number>): void;
  /** strong(i): handle i at full strength through the surface too (default: the handles not of the base colour). */
  setHandleColors(colorOf: (handle: number) => THREE.Color, strong?: ((handle: number) => boolean) | null): void;
  dispose(): void;
}

/** Opacity of a handle dot through the surface (0.3; the cage's hidden edges: 0.22). */
export const HIDDEN_HANDLE_OPACITY: number;
/** handleSize 'auto': k x the median on-screen cage edge length, within [min, max] CSS pixels (0.55, 6, 13). */
export const AUTO_HANDLE_SIZE: Readonly<{ k: number; min: number; max: number }>;
/** clamp(k x spacing, min, max) in quarter pixels; max when the spacing is not a positive number. */
export function handleSizeForSpacing(spacing: number, options?: { k?: number; min?: number; max?: number }): number;
/**
 * Median on-screen length (CSS pixels) of the edges under `matrix` (projection x view x model,
 * column-major) on a width x height view; at most `samples` (256) edges looked at; NaN when none is seen.
 */
export function medianEdgeSpacing(positions: ArrayLike<number>, edges: ArrayLike<number>, matrix: ArrayLike<number>,
  width: number, height: number, samples?: number): number;

export function edgesOf(faces: ArrayLike<number>, index?: Map<number, number> | null): Uint32Array;
/** Unique sides of quads (4 indices each): no diagonals. */
export function quadEdgesOf(quads: ArrayLike<number>, index?: Map<number, number> | null): Uint32Array;
/** Each quad (a, b, c, d) as triangles (a, b, c), (a, c, d), for drawing. */
export function trianglesOfQuads(quads: ArrayLike<number>): Uint32Array;
export function arrows(from: ArrayLike<number>, vectors: ArrayLike<number>, options?: { color?: THREE.ColorRepresentation; scale?: number }): THREE.LineSegments;
export function bounds(positions: ArrayLike<number>): { center: [number, number, number]; radius: number };
export function frameSphere(camera: THREE.PerspectiveCamera, sphere: { center: number[]; radius: number },
  options?: { controls?: { target: THREE.Vector3; update(): unknown } | null; direction?: number[]; margin?: number }): void;

export function projectPoints(positions: ArrayLike<number>, camera: THREE.Camera, width: number, height: number,
  out?: Float64Array, depths?: Float64Array | null): Float64Array;
export function nearestOnScreen(screen: ArrayLike<number>, depths: ArrayLike<number>, x: number, y: number, radius: number): number;
export function rayThrough(camera: THREE.Camera, x: number, y: number, width: number, height: number, ray?: THREE.Ray): THREE.Ray;
export class DragPlane {
  start(camera: THREE.Camera, ray: THREE.Ray, point: THREE.Vector3): boolean;
  delta(ray: THREE.Ray): [number, number, number] | null;
}

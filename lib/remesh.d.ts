// Type declarations of `mrvol/remesh` (lib/remesh.mjs): semi-regular remeshing and the repair
// stage. Apart from the core entry, so that the core's users do not load three.js, three-mesh-bvh
// and meshoptimizer.
import type { Mesh, Mrvol } from './index.js';

/** Options of remesh(). */
export interface RemeshOptions {
  /**
   * Levels of 1-to-4 splits over the base mesh (0..6). Default: from 2, as many as bring the
   * two-sided Hausdorff distance within `hausdorffGoal`, within `maxVertices`; still above it, a
   * base twice and four times as large is tried. Given, with the base (given or default) it must
   * make at most 5,242,880 faces (MAX_RESULT_FACES: the 2.6-million-vertex meshes the editor is
   * made for); more is refused at once.
   */
  levels?: number;
  /**
   * Faces of the simplified base mesh over all components (>= 4). Default: the input's face count
   * / 12 within 200..1000 (a cage of about 100-500 handles), raised to make room for the feature
   * vertices of a CAD part; a component smaller than its share is its own base (then exact). A
   * result that still folds after untangling is retried without the feature constraints, then
   * with twice and four times the base. A size given is kept once a fit on it does not fold; if
   * the first fit folds on it, it grows (1.5x to 16x, within 4x the default size) and `baseGrown` in
   * the result says so.
   */
  baseFaces?: number;
  /**
   * MAPS-style fit (default false): bases made by the topology-keeping half-edge collapse straight
   * from each piece (up to 60000 faces), which keeps every removed vertex's place on the base, and
   * the semi-regular vertices put at their place on the input by that map instead of cast and
   * relaxed (lib/remesh-param.mjs). Unset: run as well when the default fit stays above the
   * Hausdorff goal, and kept if closer without flipped triangles (see `fit` in the result); false: never.
   * An input fitted against a proxy (`proxy`) is fitted this way by default.
   */
  parametrise?: boolean;
  /**
   * A large input (over 150000 faces, no sharp features; lib/remesh-proxy.mjs) is fitted against a
   * proxy: each piece simplified by meshoptimizer to about 55000 faces over all pieces, closed, of at most
   * its genus, every input vertex within 0.04% of the diagonal of it (the far vertices locked in the
   * simplification again); the fits run parametrised against it and the chosen fit is measured,
   * dragged and nudged against the input (see `proxy` in the result). Only where the proxy is
   * small enough for the parametrised fit (inputs up to about 480k faces) and `parametrise` is not
   * false. false: never; an object overrides the settings ({ minFaces, ratio, minTarget, limit }).
   */
  proxy?: boolean | { minFaces?: number; ratio?: number; minTarget?: number; limit?: number };
  /** Keep only the largest connected component (default false: every component is remeshed). */
  keepLargest?: boolean;
  /** Default levels: the distance to reach (fraction of the diagonal, default 0.005). */
  hausdorffGoal?: number;
  /** Default levels: at most this many vertices (default max(2x the input's, 10000)). */
  maxVertices?: number;
  /** Sharp features kept (default true): see `features` in the result. */
  features?: boolean;
  /** Dihedral angle in degrees over which an edge is a crease (default 35). */
  featureAngle?: number;
  /** Run repair() on the input first (for scans that are almost a closed 2-manifold; default false). */
  repair?: boolean;
  /** With repair: the largest hole (in edges) it closes (default 100). */
  maxHoleEdges?: number;
  /**
   * With repair: Taubin smoothing iterations after it (default 0). A smoothing that collapses the
   * surface (under 1% of its volume left) is refused.
   */
  smooth?: number;
  /** Tangential relaxation steps per level (default 4). */
  relaxIterations?: number;
  /** At most this many sample points per direction for the Hausdorff distance (default 200000). */
  maxSamples?: number;
  /** Return a result with flipped triangles instead of refusing it (default false). */
  allowFlipped?: boolean;
  /**
   * A result still above `hausdorffGoal` is dragged onto the input vertices it misses (tips the base
   * cut off), kept if closer and not more folded (default true).
   */
  dragTips?: boolean;
  /**
   * A fit still above `hausdorffGoal` after the other rounds is tried again on bases of the same size
   * simplified with their faces weighted toward the regions the first fit left far; the closest fit is
   * kept (default true). A closest fit within 1.5 times the goal is first dragged and nudged
   * (dragTips, nudge), before the rounds and before each further round: they run only if that leaves
   * it above the goal.
   */
  emphasis?: boolean;
  /**
   * A fit still above `hausdorffGoal` after the emphasis rounds is tried again (up to two rounds) on a
   * base of the same size refined where the closest fit is far: the emphasised base of twice the size,
   * collapsed back with its vertices near the far input points kept, so the faces go there and the cage
   * does not grow unless that fit folds (then its base twice as large, refined the same way); the closest
   * fit is kept (default true).
   */
  refine?: boolean;
  /**
   * A result still above `hausdorffGoal` after the drag gets its farthest sample points (input points
   * far from it, its points far from the input) brought to 90% of the goal by moving the corners of
   * their triangle, off the input if need be (no farther from it than 95% of the goal); each move kept
   * only if nothing flips (no triangle turned past a cosine of -0.1 to the input's normal) and no nearby
   * sample gets farther; a move refused is tried again together with the far samples sharing its
   * corners (the least joint move); the result kept if closer (default true).
   */
  nudge?: boolean;
  /**
   * Diagnostics (bench/remesh-diagnose.mjs): called with 'fitted' (a piece's fit before untangling:
   * { piece, levels, base, mesh, flipped }), 'untangled' ({ piece, levels, mesh, flippedTriangles }) and
   * 'chosen' (the result before the drag: { mesh, measured }), 'nudging' (the result before the nudge:
   * { mesh, fixed, measured }). The meshes may be changed later: copy them.
   */
  debug?: (event: 'fitted' | 'untangled' | 'chosen' | 'nudging', data: object) => void;
  /** Called between stages with the rough fraction done (0..1) and the stage's name. */
  onProgress?: (fraction: number, stage: string) => void;
}

/** What remesh() returns. */
export interface RemeshResult {
  /** The semi-regular mesh, hierarchy order (base vertices first): openMesh() detects `levels`. */
  mesh: Mesh;
  levels: number;
  /** The level counts fitted (default levels: the search). */
  levelsTried: number[];
  /** Every fit tried: levels, base faces, flipped triangles left, Hausdorff distance. */
  fits: { levels: number; baseFaces: number; flipped: number; hausdorff?: number }[];
  /** Connected components remeshed (each with its own base). */
  components: number;
  baseVertices: number;
  baseFaces: number;
  /**
   * The first fit on the base size given (`baseFaces`) folded even untangled, so the base was made
   * larger (`to` faces asked of the simplifier) rather than give up; null otherwise.
   */
  baseGrown: { asked: number; to: number } | null;
  vertices: number;
  faces: number;
  /**
   * Two-sided sampled Hausdorff distance / bounding-box diagonal of the input (the surface fitted:
   * with `smooth`, the smoothed one; repair.smoothing says how far the smoothing moved it).
   */
  hausdorff: number;
  /** Result samples to the input surface, / diagonal. */
  hausdorffToInput: number;
  /** Input samples to the result surface, / diagonal. */
  hausdorffFromInput: number;
  diagonal: number;
  /**
   * Triangles facing clearly against the input's (smoothed) normal at their centroid's closest
   * point (cosine below -0.25) and against an edge neighbour, or degenerate: 0 unless allowFlipped.
   */
  flippedTriangles: number;
  /** Such triangles before the local untangling. */
  untangledTriangles: number;
  /**
   * Sharp features: crease edges (dihedral over featureAngle; spurs and lines under 3% of the
   * diagonal dropped as bumps, counted in ignoredAsNoise), corners, lines; base vertices held on
   * corners and vertices kept on creases in the result.
   */
  features: { edges: number; corners: number; lines: number; ignoredAsNoise: number; cornerVertices: number; creaseVertices: number };
  volumeInput: number;
  volume: number;
  /** (volume - volumeInput) / volumeInput (volumeInput: the surface fitted, smoothed with `smooth`). */
  volumeChange: number;
  /** With `smooth`: the volume change from the input as repaired, before smoothing; else null. */
  volumeChangeFromUnsmoothed: number | null;
  /** New vertices placed at the closest point because no ray hit within its cap. */
  rayFallbacks: number;
  /** droppedPieces: closed pieces that enclose no volume (fewer than 4 faces, flat double sheets). */
  input: { vertices: number; faces: number; weldedVertices: number; droppedFaces: number; droppedComponents: number; droppedPieces: number; genus: number };
  /** Pieces whose base lost tiny tunnels (a scan's genus 52) the simplifier could not keep. */
  genusChangedPieces: number;
  /** What repair() did, when the repair option was given (else null). */
  repair: RepairReport | null;
  /** Simplifier outputs that failed validation (target faces: problem), and targets not simplified because a base as large already lost the piece's genus. */
  simplifierRetries: string[];
  /** Which fit the result is: the simplifier's bases, cast and relaxed, or the MAPS fit (`parametrise`). */
  fit: 'simplified' | 'parametrised';
  /** The MAPS fit tried because the default stayed above the goal (null if not tried): its distance, or its error. */
  parametrisedFallback: { hausdorff?: number; flippedTriangles?: number; error?: string | null; kept: boolean } | null;
  /**
   * The proxy the fits ran against (see the `proxy` option), or null: its faces, the farthest input
   * vertex from it (over the diagonal), the pieces proxied, the simplifications per piece, and the
   * tunnels the proxies closed.
   */
  proxy: { faces: number; distance: number; pieces: number; rounds: number; genusLost: number } | null;
  /**
   * A fit against a proxy (parametrised by default there) that folded (`error`) or stayed above
   * `hausdorffGoal`: the input fitted without the proxy too (`proxy: false`; its distance and flipped
   * triangles here), the closer unfolded result kept; null when not run.
   */
  proxyFallback: { hausdorff: number; flippedTriangles: number; error: string | null; kept: boolean } | null;
  ms: number;
}

/** What repair() did: counts of each fix. */
export interface RepairReport {
  weldedVertices: number;
  /** Vertices no face used (a stray point, an exporter's lines), dropped. */
  unusedVertices: number;
  degenerateFaces: number;
  /** Faces repeated with the same orientation (one copy kept). */
  duplicateFaces: number;
  /** Faces cancelled in opposite pairs. */
  finFaces: number;
  /** Faces dropped on non-manifold edges and vertices. */
  nonManifoldFaces: number;
  droppedComponents: number;
  holesFilled: number;
  holeEdges: number;
  /** Holes larger than maxHoleEdges, left for validation to refuse. */
  holesLeft: number;
  largestHoleLeft?: number;
  /** Folded faces cut out and filled again. */
  foldedFaces: number;
  /** Faces turned to agree with their neighbours (a flipped patch). */
  reorientedFaces: number;
  /** Edges whose faces no orientation can make agree (a one-sided surface: refused). */
  oneSidedEdges: number;
  /** Components turned outwards (they enclosed a negative volume). */
  reversedComponents: number;
  /**
   * With `smooth`: the volume before and after the smoothing, and the largest move of a vertex
   * (/ the diagonal before it).
   */
  smoothing?: { volumeBefore: number; volumeAfter: number; largestMove: number };
  [key: string]: number | { volumeBefore: number; volumeAfter: number; largestMove: number } | undefined;
}

/**
 * The repair stage of remesh, alone: weld by position, cancel fins and drop repeated faces, drop
 * the faces of non-manifold edges and vertices, optionally keep the largest component, close holes
 * of at most maxHoleEdges edges, cut out folds and fill again, optionally smooth. Pure JS; what is
 * left wrong is for validate() to name. Throws RangeError for arrays that are not a mesh (not 3
 * numbers per vertex and 3 indices per face, an index past the last vertex, a non-finite coordinate).
 */
export function repair(mesh: Mesh, options?: { keepLargest?: boolean; maxHoleEdges?: number; smooth?: number }):
  { mesh: Mesh; report: RepairReport };

/**
 * Semi-regular remeshing of closed manifold triangle meshes (welded first; several components,
 * any genus): meshoptimizer simplification of each component to a base mesh (closed, manifold,
 * same genus, feature vertices kept), n levels of 1-to-4 splits fitted to the input
 * (three-mesh-bvh) with corners held and crease vertices kept on their creases, tangential
 * relaxation, local untangling of folds. Rejects with MrvolError naming the problem: arrays that
 * are not a mesh (an index past the last vertex, a non-finite coordinate), holes,
 * non-manifold input (both: try repair), a one-sided surface, no volume, a fold that no retry removes.
 * `mrvol` is the API object of createMrvol().
 */
export function remesh(mrvol: Mrvol, mesh: Mesh, options?: RemeshOptions): Promise<RemeshResult>;

/**
 * Merges vertices with identical coordinates (after rounding to 1e-9 of the bounding-box
 * diagonal), drops faces that become degenerate and vertices no face uses. Throws RangeError as
 * repair() does.
 */
export function weld(mesh: Mesh): Mesh & { merged: number; droppedFaces: number };

/** remesh()'s default base size (faces over all components) for an input of `inputFaces` faces. */
export function defaultBaseFaces(inputFaces: number): number;

/** The most faces remesh() makes with levels given (5,242,880: the 2.6-million-vertex meshes the editor is made for). */
export const MAX_RESULT_FACES: number;

// Type declarations of `mrvol/remesh` (lib/remesh.mjs): semi-regular remeshing and the repair
// stage. Apart from the core entry, so that the core's users do not load three.js, three-mesh-bvh
// and meshoptimizer.
import type { Mesh, Mrvol } from './index.js';

/** Options of remesh(). */
export interface RemeshOptions {
  /** Levels of 1-to-4 splits over the base mesh (0..6, default 2). */
  levels?: number;
  /**
   * Faces of the simplified base mesh (>= 4). Default: the input's face count / 4^levels within
   * 300..8000; then a folded result is retried with twice the base (3 attempts).
   */
  baseFaces?: number;
  /** Keep the largest connected component instead of refusing several (default false). */
  keepLargest?: boolean;
  /** Run repair() on the input first (for scans that are almost a closed 2-manifold; default false). */
  repair?: boolean;
  /** With repair: the largest hole (in edges) it closes (default 100). */
  maxHoleEdges?: number;
  /** With repair: Taubin smoothing iterations after it (default 0). */
  smooth?: number;
  /** Tangential relaxation steps per level (default 4). */
  relaxIterations?: number;
  /** At most this many sample points per direction for the Hausdorff distance (default 200000). */
  maxSamples?: number;
  /** Return a result with flipped triangles instead of refusing it (default false). */
  allowFlipped?: boolean;
  /** Called between stages with the rough fraction done (0..1) and the stage's name. */
  onProgress?: (fraction: number, stage: string) => void;
}

/** What remesh() returns. */
export interface RemeshResult {
  /** The semi-regular mesh, hierarchy order (base vertices first): openMesh() detects `levels`. */
  mesh: Mesh;
  levels: number;
  baseVertices: number;
  baseFaces: number;
  vertices: number;
  faces: number;
  /** Two-sided sampled Hausdorff distance / bounding-box diagonal of the input. */
  hausdorff: number;
  /** Result samples to the input surface, / diagonal. */
  hausdorffToInput: number;
  /** Input samples to the result surface, / diagonal. */
  hausdorffFromInput: number;
  diagonal: number;
  /** Triangles facing against the input's (smoothed) normal at their centroid's closest point. */
  flippedTriangles: number;
  volumeInput: number;
  volume: number;
  /** (volume - volumeInput) / volumeInput. */
  volumeChange: number;
  /** New vertices placed at the closest point because no ray hit within its cap. */
  rayFallbacks: number;
  input: { vertices: number; faces: number; weldedVertices: number; droppedFaces: number; droppedComponents: number; genus: number };
  /** What repair() did, when the repair option was given (else null). */
  repair: RepairReport | null;
  /** Simplifier outputs that failed validation (target faces: problem). */
  simplifierRetries: string[];
  ms: number;
}

/** What repair() did: counts of each fix. */
export interface RepairReport {
  weldedVertices: number;
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
  [key: string]: number | undefined;
}

/**
 * The repair stage of remesh, alone: weld by position, cancel fins and drop repeated faces, drop
 * the faces of non-manifold edges and vertices, optionally keep the largest component, close holes
 * of at most maxHoleEdges edges, cut out folds and fill again, optionally smooth. Pure JS; what is
 * left wrong is for validate() to name.
 */
export function repair(mesh: Mesh, options?: { keepLargest?: boolean; maxHoleEdges?: number; smooth?: number }):
  { mesh: Mesh; report: RepairReport };

/**
 * Semi-regular remeshing of a closed manifold triangle mesh (welded first): meshoptimizer
 * simplification to a base mesh (closed, manifold, same genus), n levels of 1-to-4 splits fitted
 * to the input (three-mesh-bvh), tangential relaxation. Rejects with MrvolError naming the
 * problem: holes, several components (unless keepLargest), non-manifold input, a folded result.
 * `mrvol` is the API object of createMrvol().
 */
export function remesh(mrvol: Mrvol, mesh: Mesh, options?: RemeshOptions): Promise<RemeshResult>;

/**
 * Merges vertices with identical coordinates (after rounding to 1e-9 of the bounding-box
 * diagonal), drops faces that become degenerate and vertices no face uses.
 */
export function weld(mesh: Mesh): Mesh & { merged: number; droppedFaces: number };

/** remesh()'s default base size for an input of `inputFaces` faces and `levels` levels. */
export function defaultBaseFaces(inputFaces: number, levels: number): number;

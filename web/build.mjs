// Builds the console's bundle: the protocol's JavaScript from the .proto
// files (protoc with protoc-gen-es), then one app.js with three.js and the
// protobuf runtime (esbuild), next to index.html and style.css.
//   node build.mjs OUT_DIR
// HAPSIM_WEB_MINIFY=0 keeps the names (for a profile of the page).
import { execFileSync } from "node:child_process";
import { copyFileSync, mkdirSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import * as esbuild from "esbuild";

const here = dirname(fileURLToPath(import.meta.url));
const out = resolve(process.argv[2] || join(here, "dist"));
const gen = join(out, "gen");
mkdirSync(gen, { recursive: true });
const protoDir = join(here, "..", "proto");
execFileSync("protoc", [
  `--plugin=protoc-gen-es=${join(here, "node_modules", ".bin", "protoc-gen-es")}`,
  `--es_out=${gen}`, "--es_opt=target=js", `-I${protoDir}`,
  ...["session", "viewer", "console"].map((p) => join(protoDir, "hapsim", "v1", `${p}.proto`)),
], { stdio: "inherit" });
await esbuild.build({
  entryPoints: [join(here, "src", "main.js")],
  bundle: true,
  minify: process.env.HAPSIM_WEB_MINIFY !== "0",
  sourcemap: false,
  format: "iife",
  target: ["chrome110", "firefox110", "safari16"],
  outfile: join(out, "app.js"),
  alias: { "hapsim-proto": join(gen, "hapsim", "v1") },
  nodePaths: [join(here, "node_modules")],
  logLevel: "warning",
});
for (const f of ["index.html", "style.css"]) copyFileSync(join(here, f), join(out, f));
console.log(`web console built into ${out}`);

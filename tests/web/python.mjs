// The checkout's Python for the Node tests' oracles (FROST_PYTHON, which tests/test_web_node.py
// sets; this checkout's .venv otherwise), run from tests/ so `support.*` imports.

import { execFileSync } from "node:child_process";
import path from "node:path";
import { fileURLToPath } from "node:url";

export const ROOT = process.env.FROST_ROOT
  ?? path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
const PYTHON = process.env.FROST_PYTHON ?? path.join(ROOT, ".venv/bin/python");

// Python run with `args`; its standard output as text.
export function python(...args) {
  return execFileSync(PYTHON, args, {
    cwd: path.join(ROOT, "tests"), encoding: "utf-8", maxBuffer: 1 << 28,
    stdio: ["ignore", "pipe", "inherit"],
    env: { ...process.env, PYTHONPATH: [ROOT, path.join(ROOT, "tests")].join(path.delimiter) },
  });
}

// A preset's Params as the page is given them (snake_case, dataclasses.asdict).
export function presetParams(name) {
  return JSON.parse(python("-c", "import dataclasses, json, sys; from sim import Params; "
    + "print(json.dumps(dataclasses.asdict(Params.preset(sys.argv[1]))))", name));
}

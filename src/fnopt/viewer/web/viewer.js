// fnopt view's page (docs/design.md §11): one rollout (fnopt view FILE), or a compare
// directory's chart (fnopt view DIR) whose kept rollouts open at /?run=ROW.
import { showCompareChart } from "/compare_chart.js";
import { showRollout } from "/rollout_player.js";

async function json(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim() || response.status}`);
  return response.json();
}

async function start() {
  const session = await json("/api/session");
  const run = new URLSearchParams(location.search).get("run");
  if (session.mode === "rollout") return showRollout(session.rollout);
  if (run !== null) {
    document.getElementById("back").hidden = false;
    return showRollout(Number(run));
  }
  return showCompareChart(await json("/api/compare"));
}

start().catch((error) => {
  document.getElementById("status").textContent = `error: ${error.message}`;
});

using System.Collections.Generic;
using System.IO;
using Toyroom.Engine;
using Toyroom.Protocol;

namespace Toyroom.Samples.GridEngine
{
    /// <summary>The grid world as an <see cref="IEngine"/>: scenarios by name from a folder of exports.</summary>
    public sealed class GridGame : IEngine
    {
        public const double TickSeconds = 0.7; // one cell per tick, as the Python grid engine
        private readonly string folder;
        private readonly bool? robotOverride;
        private ScenarioFile scenario;
        private GridWorld world;
        private long episode;

        public GridGame(string folder, string scenarioName, bool? robotOverride)
        {
            this.folder = folder;
            this.robotOverride = robotOverride;
            Load(scenarioName);
        }

        private void Load(string name)
        {
            // a name, an export's path, or a .toml path whose export lies in the folder by its stem
            var stem = name.EndsWith(".toml") ? Path.GetFileNameWithoutExtension(name) : name;
            var path = name.EndsWith(".json") ? name : Path.Combine(folder, stem + ".json");
            if (!File.Exists(path)) throw new UnknownScenario("no scenario '" + name + "' (no " + path + ")");
            var next = ScenarioFile.Read(path);
            scenario = next;
            world = new GridWorld(scenario, episode, TickSeconds, robotOverride ?? scenario.RobotActs);
        }

        public EngineInfo Describe()
        {
            var scene = scenario.Scene;
            foreach (var agent in scene.Agents)
                agent.Acts = agent.Kind != AgentKind.Robot || world.RobotActs;
            return new EngineInfo
            {
                Engine = "toyroom C# grid engine 0.1 (sample)",
                Scenario = scenario.Name,
                Capabilities = new List<string> { "lockstep", "robot" },
                Clock = ClockMode.Lockstep,
                TickSeconds = TickSeconds,
                Episode = episode,
                Scene = scene,
            };
        }

        public State Reset(string name, long seed)
        {
            episode++;
            try
            {
                Load(name ?? scenario.Name);
            }
            catch (UnknownScenario)
            {
                episode--; // a failed reset starts no episode
                throw;
            }
            return world.State();
        }

        public TickResult Tick()
        {
            world.Step();
            return new TickResult { Events = world.Events, Statuses = world.Statuses, State = world.State() };
        }

        public List<CommandStatus> Command(RobotCommand command)
        {
            world.Statuses = new List<CommandStatus>();
            world.Receive(command);
            return world.Statuses;
        }

        public State Current { get { return world.State(); } }
    }
}

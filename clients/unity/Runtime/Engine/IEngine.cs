using System;
using System.Collections.Generic;
using Toyroom.Protocol;

namespace Toyroom.Engine
{
    /// <summary>What one tick produced: its events (in order), command statuses, and the state after it.</summary>
    public sealed class TickResult
    {
        public List<Event> Events = new List<Event>();
        public List<CommandStatus> Statuses = new List<CommandStatus>();
        public State State;
    }

    /// <summary>A scenario name the engine does not have (answered with <c>unknown_scenario</c>).</summary>
    public sealed class UnknownScenario : Exception
    {
        public UnknownScenario(string message) : base(message) { }
    }

    /// <summary>
    /// A game the brain can drive. <see cref="EngineHost"/> calls every method on the thread
    /// that calls <see cref="EngineHost.Pump"/> (Unity's main thread), never concurrently.
    /// </summary>
    public interface IEngine
    {
        /// <summary>The handshake: engine name, capabilities, clock, episode, the scene.</summary>
        EngineInfo Describe();

        /// <summary>Start a new episode of <paramref name="scenario"/> (null: the current one); the first state.</summary>
        /// <exception cref="UnknownScenario">no such scenario: the episode does not change.</exception>
        State Reset(string scenario, long seed);

        /// <summary>Advance exactly one tick.</summary>
        TickResult Tick();

        /// <summary>A robot command arrived: the statuses it causes at once (accepted or failed).</summary>
        List<CommandStatus> Command(RobotCommand command);

        /// <summary>The state now.</summary>
        State Current { get; }
    }
}

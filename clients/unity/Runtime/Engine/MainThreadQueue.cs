using System;
using System.Collections.Concurrent;
using System.Threading;

namespace Toyroom.Engine
{
    /// <summary>
    /// Work handed from network threads to the one thread that may touch the game (Unity's
    /// main thread): <see cref="Post"/> from anywhere, <see cref="RunPending"/> there.
    /// </summary>
    public sealed class MainThreadQueue
    {
        private readonly ConcurrentQueue<Action> work = new ConcurrentQueue<Action>();
        private readonly AutoResetEvent posted = new AutoResetEvent(false);

        public void Post(Action action)
        {
            work.Enqueue(action);
            posted.Set();
        }

        /// <summary>Run everything posted so far; how many ran.</summary>
        public int RunPending()
        {
            var ran = 0;
            Action action;
            while (work.TryDequeue(out action))
            {
                action();
                ran++;
            }
            return ran;
        }

        /// <summary>Block until something is posted or <paramref name="timeout"/> passes.</summary>
        public bool Wait(TimeSpan timeout)
        {
            return !work.IsEmpty || posted.WaitOne(timeout);
        }
    }
}
